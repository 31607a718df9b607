// dynpm batch: every variant of a list built into one folder, several at once on this machine or
// as a Slurm job array; then the folder's catalogue (index.json).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

#include "args.h"
#include "batch_list.h"
#include "batch_slurm.h"
#include "catalogue.h"
#include "commands.h"
#include "dynpm/core.h"
#include "dynpm/progressive.h"
#include "inputs.h"
#include "processes.h"
#include "report.h"
#include "shared_flags.h"

namespace dynpm::cli {
namespace {

// The flags 'dynpm batch' hands to every 'dynpm build' as they were given.
const FlagSpec* const kBuildFlags[] = {
    &kKeyStepsFlag,       &kLosslessFlag,      &kPositionErrorFlag,   &kFieldBoundFlag,
    &kBoundaryWeightFlag, &kFieldFlag,         &kFieldWeightFlag,     &kFieldCostFlag,
    &kRegularizeFlag,     &kRoundsFlag,        &kIgnorePartsFlag,     &kThreadsFlag,
    &kNoMemoryCheckFlag,  &kSplitPolygonsFlag, &kIntegrationPointFlag};

VerbSpec make_spec() {
  VerbSpec spec{
      "batch",
      "dynpm batch LIST --out DIR [--jobs N] [--force] [--dry-run] [build options]\n"
      "       dynpm batch LIST --out DIR --slurm [--partition P] [--time HH:MM:SS] [--mem M]\n"
      "                   [--max-running K] [--dry-run] [build options]",
      "Builds every input named in LIST (one a line, or a glob; '#' starts a comment; relative\n"
      "to LIST's folder) into DIR/<name>.dpm, <name> being the input's file name without its\n"
      "extension. A .dpm newer than its input is kept (--force builds it again); a build that is\n"
      "killed leaves no .dpm, so running the batch again goes on where it stopped. Each build\n"
      "logs to DIR/logs/<name>.log (JSON progress lines). Then prints a table of the builds\n"
      "and writes the catalogue DIR/index.json ('dynpm catalogue'). Exit code 1 when a build\n"
      "failed. With --slurm, submits a Slurm job array (one task per input) and a job that\n"
      "writes the catalogue after them (docs/batch.md).",
      {{"--out", "-o", true, "DIR", "the folder of the .dpm files (made when missing)"},
       {"--jobs", "-j", true, "N", "builds at once (default 1); each gets cores/N threads"},
       {"--force", "", false, "", "build even the variants whose .dpm is up to date"},
       {"--dry-run", "", false, "", "print what would be built (or submitted) and stop"},
       {"--slurm", "", false, "", "submit to Slurm with sbatch instead of building here"},
       {"--partition", "", true, "P", "Slurm partition"},
       {"--time", "", true, "HH:MM:SS", "Slurm time limit of each build"},
       {"--mem", "", true, "M", "Slurm memory of each build (e.g. 8G)"},
       {"--max-running", "", true, "K", "Slurm: at most K builds at once (--array=…%K)"},
       {"--task", "", true, "I", "build only input I (from 0): what a Slurm array task runs"},
       kQuietFlag}};
  for (const FlagSpec* flag : kBuildFlags) spec.flags.push_back(*flag);
  return spec;
}
const VerbSpec kSpec = make_spec();

enum class Outcome { kPlanned, kBuilt, kSkipped, kFailed };
const char* to_string(Outcome o) {
  switch (o) {
    case Outcome::kPlanned: return "to build";
    case Outcome::kBuilt: return "built";
    case Outcome::kSkipped: return "skipped";
    case Outcome::kFailed: return "failed";
  }
  return "";
}

struct Job {
  BatchInput input;
  std::string dpm, log;
  Outcome outcome = Outcome::kPlanned;
  double seconds = 0;
  uint64_t bytes = 0, vertices = 0;
  std::string message;
};

// The flags for every build, as "--name=value" (one word each, whatever the value holds); with
// `share_cores`, --threads for `jobs` builds at once on this machine or in this Slurm task.
std::vector<std::string> build_flags(const Args& args, size_t jobs, bool share_cores) {
  std::vector<std::string> flags;
  for (const FlagSpec* flag : kBuildFlags) {
    if (!flag->takes_value) {
      if (args.has(flag->name)) flags.push_back(flag->name);
      continue;
    }
    for (const std::string& value : args.values(flag->name))
      flags.push_back(flag->name + "=" + value);
  }
  if (args.has("--threads") || !share_cores) return flags;
  // A Slurm task has the CPUs Slurm gave it, not the node's; N builds at once share the cores
  // instead of each taking them all.
  if (const char* slurm_cpus = std::getenv("SLURM_CPUS_ON_NODE"); slurm_cpus && jobs == 1) {
    if (auto cpus = parse_whole("SLURM_CPUS_ON_NODE", slurm_cpus, 1, kMaxThreads))
      flags.push_back("--threads=" + std::to_string(*cpus));
  } else if (jobs > 1) {
    flags.push_back("--threads=" + std::to_string(std::max<size_t>(
                                       1, std::thread::hardware_concurrency() / jobs)));
  }
  return flags;
}

// What a failed build said last: its "dynpm build: …" line, else how it ended.
std::string failure_message(const std::string& log, const std::string& how_it_ended) {
  std::ifstream in(log);
  std::string said;
  const std::string prefix = "dynpm build: ";
  for (std::string line; std::getline(in, line);)
    if (line.starts_with(prefix)) said = line.substr(prefix.size());
  return said.empty() ? how_it_ended : said;
}

// Size and vertex count of a .dpm from its header (nothing past the base mesh is decoded).
void describe_output(Job& job) {
  std::error_code ec;
  job.bytes = std::filesystem::file_size(job.dpm, ec);
  DpmReadLimits limits;
  limits.fields = false;
  limits.vertices = 1;
  limits.last_step = 0;
  if (auto mesh = read_dpm(job.dpm, limits)) job.vertices = mesh->full_vertex_count;
}

// Runs the planned jobs, `parallel` at once, as children of this program: "dynpm build INPUT
// -o DIR/NAME.dpm", which writes under a temporary name and renames when complete.
Status run_jobs(std::vector<Job>& jobs, size_t parallel, const std::vector<std::string>& flags,
                bool quiet) {
  auto self = own_executable();
  if (!self) return self.status();
  using Clock = std::chrono::steady_clock;
  std::map<pid_t, std::pair<Job*, Clock::time_point>> running;
  auto next = jobs.begin();
  for (;;) {
    while (running.size() < parallel && next != jobs.end()) {
      Job& job = *next++;
      if (job.outcome != Outcome::kPlanned) continue;
      remove_stale_temporaries(job.dpm);
      std::remove(job.log.c_str());  // the log of this build only
      std::vector<std::string> argv = {*self,   "build",      job.input.path, "-o",
                                       job.dpm, "--progress", "json",         "--json"};
      argv.insert(argv.end(), flags.begin(), flags.end());
      auto pid = start_process(argv, job.log);
      if (!pid) {
        job.outcome = Outcome::kFailed;
        job.message = pid.message();
        continue;
      }
      if (!quiet) std::fprintf(stderr, "dynpm batch: building %s\n", job.input.name.c_str());
      running.emplace(*pid, std::make_pair(&job, Clock::now()));
    }
    if (running.empty()) return {};
    auto ended = wait_for_any_child();
    if (!ended) return ended.status();
    auto it = running.find(ended->pid);
    if (it == running.end()) continue;
    Job& job = *it->second.first;
    job.seconds = std::chrono::duration<double>(Clock::now() - it->second.second).count();
    running.erase(it);
    job.outcome = ended->failure.empty() ? Outcome::kBuilt : Outcome::kFailed;
    if (job.outcome == Outcome::kFailed) job.message = failure_message(job.log, ended->failure);
    if (!quiet)
      std::fprintf(stderr, "dynpm batch: %s %s (%.1f s)\n", job.input.name.c_str(),
                   to_string(job.outcome), job.seconds);
  }
}

// "input  status  time  size  vertices  message", one row a variant.
void print_summary(const std::vector<Job>& jobs) {
  size_t width = 5;
  for (const Job& job : jobs) width = std::max(width, job.input.path.size());
  std::printf("%-*s  %-8s  %8s  %12s  %9s  %s\n", int(width), "input", "status", "time_s", "bytes",
              "vertices", "message");
  for (const Job& job : jobs) {
    const bool has_file = job.outcome == Outcome::kBuilt || job.outcome == Outcome::kSkipped;
    char time[32] = "-", bytes[32] = "-", vertices[32] = "-";
    if (job.outcome == Outcome::kBuilt || job.outcome == Outcome::kFailed)
      std::snprintf(time, sizeof time, "%.2f", job.seconds);
    if (has_file) {
      std::snprintf(bytes, sizeof bytes, "%llu", static_cast<unsigned long long>(job.bytes));
      std::snprintf(vertices, sizeof vertices, "%llu",
                    static_cast<unsigned long long>(job.vertices));
    }
    std::printf("%-*s  %-8s  %8s  %12s  %9s  %s\n", int(width), job.input.path.c_str(),
                to_string(job.outcome), time, bytes, vertices, job.message.c_str());
  }
}

Result<uint64_t> whole_flag(const Args& args, const std::string& flag, uint64_t fallback,
                            uint64_t min, uint64_t max) {
  auto text = args.value(flag);
  return text ? parse_whole(flag, *text, min, max) : Result<uint64_t>(fallback);
}

// --slurm: the request from the flags (checked before anything is written).
int submit(const Args& args, const std::string& out, std::vector<BatchInput> inputs) {
  auto self = own_executable();
  if (!self) return fail(kSpec.name, kExitFailure, self.message());
  SlurmRequest request;
  request.dynpm = *self;
  request.out = std::filesystem::absolute(out).lexically_normal().string();
  request.inputs = std::move(inputs);
  request.build_flags = build_flags(args, 1, false);
  if (args.has("--force")) request.build_flags.push_back("--force");  // each task rebuilds
  request.partition = args.value("--partition").value_or("");
  request.time = args.value("--time").value_or("");
  request.mem = args.value("--mem").value_or("");
  auto max_running = whole_flag(args, "--max-running", 0, 1, 1'000'000);
  if (!max_running) return fail(kSpec.name, kExitUsage, max_running.message());
  request.max_running = *max_running;
  request.dry_run = args.has("--dry-run");
  if (Status s = submit_to_slurm(request); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  return kExitOk;
}

}  // namespace

int run_batch(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  const auto out = args.value("--out");
  if (args.positional.size() != 1 || !out)
    return fail(kSpec.name, kExitUsage, "needs one LIST and --out DIR", help_text(kSpec));
  // The build flags are checked here, once, rather than failing every build.
  SimplifyOptions simplify;
  KeyStepRule key_rule;
  if (Status s = parse_simplify_flags(args, simplify, key_rule); !s.ok())
    return fail(kSpec.name, kExitUsage, s.message());
  if (auto q = parse_quantization_flags(args); !q) return fail(kSpec.name, kExitUsage, q.message());
  auto jobs_at_once = whole_flag(args, "--jobs", 1, 1, kMaxThreads);
  if (!jobs_at_once) return fail(kSpec.name, kExitUsage, jobs_at_once.message());
  for (const char* flag : {"--partition", "--time", "--mem", "--max-running"})
    if (args.has(flag) && !args.has("--slurm"))
      return fail(kSpec.name, kExitUsage, std::string(flag) + " needs --slurm");
  if (args.has("--slurm") && args.has("--task"))
    return fail(kSpec.name, kExitUsage, "--task is what a Slurm task runs; not with --slurm");

  auto inputs = read_batch_list(args.positional[0]);
  if (!inputs) return fail(kSpec.name, kExitFailure, inputs.message());
  if (args.has("--slurm")) return submit(args, *out, std::move(*inputs));
  const bool task = args.has("--task");
  if (task) {
    auto index = whole_flag(args, "--task", 0, 0, inputs->size() - 1);
    if (!index) return fail(kSpec.name, kExitUsage, index.message());
    *inputs = {(*inputs)[*index]};
  }

  const std::filesystem::path dir(*out), logs = dir / "logs";
  std::vector<Job> jobs;
  for (BatchInput& input : *inputs) {
    Job job;
    job.input = std::move(input);
    job.dpm = (dir / (job.input.name + ".dpm")).string();
    job.log = (logs / (job.input.name + ".log")).string();
    if (!args.has("--force") && is_up_to_date(job.dpm, job.input.path)) {
      job.outcome = Outcome::kSkipped;
      job.message = "up to date";
      describe_output(job);
    }
    jobs.push_back(std::move(job));
  }
  if (args.has("--dry-run")) {
    print_summary(jobs);
    return kExitOk;
  }
  std::error_code ec;
  std::filesystem::create_directories(logs, ec);
  if (ec)
    return fail(kSpec.name, kExitFailure, logs.string() + ": cannot make it: " + ec.message());
  const bool quiet = args.has("--quiet");
  if (Status s = run_jobs(jobs, *jobs_at_once, build_flags(args, *jobs_at_once, true), quiet);
      !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  for (Job& job : jobs)
    if (job.outcome == Outcome::kBuilt) describe_output(job);
  print_summary(jobs);
  std::fflush(stdout);

  std::string failed;
  for (const Job& job : jobs)
    if (job.outcome == Outcome::kFailed)
      failed += (failed.empty() ? "" : ", ") + job.input.path + " (line " +
                std::to_string(job.input.line) + ")";
  if (!task) {  // a Slurm task leaves the catalogue to the job after the array
    auto index = write_catalogue_index(*out);
    if (!index) return fail(kSpec.name, kExitFailure, index.message());
    for (const std::string& problem : index->problems) note(kSpec.name, problem);
  }
  if (!failed.empty()) return fail(kSpec.name, kExitFailure, "failed: " + failed);
  return kExitOk;
}

}  // namespace dynpm::cli
