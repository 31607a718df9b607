#include "report.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <iostream>

#include "commands.h"

namespace dynpm::cli {

int fail(const std::string& verb, int exit_code, const std::string& message,
         const std::string& help) {
  std::cerr << "dynpm " << verb << ": " << message << "\n";
  if (!help.empty()) std::cerr << "\n" << help;
  return exit_code;
}

void note(const std::string& verb, const std::string& message) {
  clear_progress_line();
  std::cerr << "dynpm " << verb << ": note: " << message << "\n";
}

namespace {
const char* failed_phase = nullptr;
}  // namespace

Phase::Phase(const char* what) : what_(what), exceptions_(std::uncaught_exceptions()) {}

Phase::~Phase() {
  if (std::uncaught_exceptions() > exceptions_ && !failed_phase) failed_phase = what_;
}

const char* Phase::failed() { return failed_phase; }

int out_of_memory(const std::string& verb) {
  std::string limit;
  if (rlimit r{}; ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    limit = "; address-space limit " + std::to_string(r.rlim_cur >> 20) + " MB (ulimit -v)";
  else if (const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
           pages > 0 && size > 0)
    limit = "; the machine has " + std::to_string((uint64_t(pages) * uint64_t(size)) >> 20) + " MB";
  const char* phase = Phase::failed();
  char peak[64];
  std::snprintf(peak, sizeof peak, "%.0f", peak_rss_mb());
  return fail(verb, kExitFailure,
              std::string("out of memory") + (phase ? " while " : "") + (phase ? phase : "") +
                  " (peak " + peak + " MB resident" + limit + ")");
}

double of_diagonal(double length, double diagonal) {
  return diagonal > 0 && std::isfinite(diagonal) ? length / diagonal : 0.0;
}

double peak_rss_mb() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  double kb = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmHWM: %lf kB", &kb) == 1) break;
  std::fclose(f);
  return kb / 1024.0;
}

}  // namespace dynpm::cli
