// Command line, timing, peak RSS and the one-line JSON report shared by the peer drivers.
//
// Every driver:   PEER INPUT.obj -o OUTPUT.obj --vertices N
// and prints one JSON line on stdout (the contract bench/simplify_bench.py reads):
//   {"peer":..,"input":..,"vertices_in":..,"faces_in":..,"target_vertices":..,
//    "vertices_out":..,"faces_out":..,"seconds":..,"peak_rss_mb":.., <extra fields>}
// "seconds" is the simplification only (no file I/O, no building of the library's mesh
// structure: that is "setup_seconds"). "peak_rss_mb" is the process peak (VmHWM): input mesh,
// library structures and output included.
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "obj_io.h"

namespace peers {

struct Args {
  std::string input, output;
  std::size_t vertices = 0;
};

inline Args parse_args(int argc, char** argv, const char* peer) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    std::string s = argv[i];
    if ((s == "-o" || s == "--output") && i + 1 < argc)
      a.output = argv[++i];
    else if ((s == "--vertices" || s == "-n") && i + 1 < argc)
      a.vertices = std::strtoull(argv[++i], nullptr, 10);
    else if (!s.empty() && s[0] != '-' && a.input.empty())
      a.input = s;
    else {
      std::fprintf(stderr, "%s: unknown argument '%s'\n", peer, s.c_str());
      std::exit(2);
    }
  }
  if (a.input.empty() || a.output.empty() || a.vertices == 0) {
    std::fprintf(stderr, "usage: %s INPUT.obj -o OUTPUT.obj --vertices N\n", peer);
    std::exit(2);
  }
  return a;
}

[[noreturn]] inline void die(const char* peer, const std::string& msg) {
  std::fprintf(stderr, "%s: %s\n", peer, msg.c_str());
  std::exit(1);
}

class Timer {
 public:
  Timer() : t0_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

 private:
  std::chrono::steady_clock::time_point t0_;
};

// Peak RSS of this process image: VmHWM from /proc/self/status. Not getrusage's ru_maxrss:
// Linux carries the parent's high-water mark across fork+exec into it, so a driver started
// by a 14 MB Python process would never report less than 14 MB.
inline double peak_rss_mb() {
  if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    long kb = -1;
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "VmHWM: %ld kB", &kb) == 1) break;
    std::fclose(f);
    if (kb >= 0) return static_cast<double>(kb) / 1024.0;
  }
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // KiB on Linux
}

inline std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      o += b;
    } else
      o += c;
  }
  return o + "\"";
}

// Builds the JSON line in insertion order.
class Json {
 public:
  Json& add(const std::string& k, const std::string& v) { return raw(k, json_string(v)); }
  Json& add(const std::string& k, const char* v) { return raw(k, json_string(v)); }
  Json& add(const std::string& k, double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return raw(k, b);
  }
  Json& add(const std::string& k, std::size_t v) { return raw(k, std::to_string(v)); }
  Json& add(const std::string& k, int v) { return raw(k, std::to_string(v)); }
  Json& add(const std::string& k, bool v) { return raw(k, v ? "true" : "false"); }
  void print() const {
    std::string o = "{";
    for (std::size_t i = 0; i < kv_.size(); ++i) {
      if (i) o += ", ";
      o += json_string(kv_[i].first) + ": " + kv_[i].second;
    }
    std::printf("%s}\n", o.c_str());
    std::fflush(stdout);
  }

 private:
  Json& raw(const std::string& k, std::string v) {
    kv_.emplace_back(k, std::move(v));
    return *this;
  }
  std::vector<std::pair<std::string, std::string>> kv_;
};

// The keys every driver reports (the contract above); each driver adds its own after them.
inline Json result_json(const char* peer, const Args& args, const TriSoup& in, std::size_t target,
                        std::size_t vertices_out, std::size_t faces_out, double seconds,
                        double setup_seconds) {
  Json j;
  j.add("peer", peer)
      .add("input", args.input)
      .add("vertices_in", in.V.size())
      .add("faces_in", in.faces_in)
      .add("target_vertices", target)
      .add("vertices_out", vertices_out)
      .add("faces_out", faces_out)
      .add("seconds", seconds)
      .add("peak_rss_mb", peak_rss_mb())
      .add("triangles_in", in.F.size())
      .add("setup_seconds", setup_seconds);
  return j;
}

}  // namespace peers
