#include "progress.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace dynpm::cli {
namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

enum class Form { kLive, kPlain, kJson, kNone };

// A plain or json line is due this long after the one before: with the ticker's period and a
// loaded machine's delays on top (up to 0.4 s measured at load 16 on 2 cores), a line at least
// every 5 s.
constexpr auto kLineEvery = std::chrono::milliseconds(4500);
constexpr auto kTick = std::chrono::milliseconds(100);
// The live line is redrawn at most this often by progress() (a terminal is slow), and by the
// ticker once a second so that elapsed time and time left move during a long library call.
constexpr auto kDrawEvery = std::chrono::milliseconds(100);
constexpr auto kRedrawEvery = std::chrono::seconds(1);

std::string duration_text(double s) {
  char text[48];
  if (s < 10)
    std::snprintf(text, sizeof text, "%.1f s", s);
  else if (s < 60)
    std::snprintf(text, sizeof text, "%.0f s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%.0f min %02.0f s", std::floor(s / 60), std::fmod(s, 60));
  else
    std::snprintf(text, sizeof text, "%.0f h %02.0f min", std::floor(s / 3600),
                  std::floor(std::fmod(s, 3600) / 60));
  return text;
}

// Items per second: "0.42/s" for steps that take seconds, "81000/s" for vertices.
std::string rate_text(double rate) {
  char text[32];
  std::snprintf(text, sizeof text, rate < 10 ? "%.2g/s" : "%.0f/s", rate);
  return text;
}

class Reporter {
 public:
  ~Reporter() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (ticker_.joinable()) ticker_.join();
  }

  void configure(Form form, const std::string& verb) {
    const std::lock_guard<std::mutex> lock(mutex_);
    form_ = form;
    verb_ = verb;
  }

  void update(std::string_view phase, size_t done, size_t total) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (form_ == Form::kNone) return;
    // A phase told its end twice (a walk reaching the count, then the caller's closing call)
    // ends once.
    if (ended_ && phase == phase_ && done >= total) return;
    const Clock::time_point now = Clock::now();
    if (phase != phase_ || ended_) {
      if (!ended_) end_phase(now);
      phase_ = phase;
      start_ = now;  // last_line_ stays: the next line is due 5 s after the last one printed
      ended_ = false;
    }
    done_ = done;
    total_ = total;
    if (done >= total) {
      end_phase(now);
    } else if (form_ == Form::kLive ? now - last_line_ >= kDrawEvery
                                    : now - last_line_ >= kLineEvery) {
      show(now);
    }
    start_ticker();
  }

  void clear_line() {
    const std::lock_guard<std::mutex> lock(mutex_);
    clear_live_line();
  }

  void remark(const std::string& text, const std::string& json) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (form_ == Form::kNone) return;
    clear_live_line();
    if (form_ == Form::kJson)
      std::fprintf(stderr, "%s\n", json.c_str());
    else
      std::fprintf(stderr, "dynpm %s: %s\n", verb_.c_str(), text.c_str());
  }

 private:
  void start_ticker() {
    if (ticker_.joinable()) return;
    try {
      ticker_ = std::thread([this] { tick(); });
    } catch (...) {  // no thread: lines come with progress() calls only
    }
  }

  void tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, kTick, [this] { return stop_; })) {
      if (form_ == Form::kNone || phase_.empty()) continue;
      const Clock::time_point now = Clock::now();
      if (ended_) {  // work between two phases that names none: said as such, on time
        if (form_ != Form::kLive && now - last_line_ >= kLineEvery) {
          try {
            show_gap(now);
          } catch (...) {
          }
        }
        continue;
      }
      if (now - last_line_ >=
          (form_ == Form::kLive ? Clock::duration(kRedrawEvery) : Clock::duration(kLineEvery))) {
        try {
          show(now);
        } catch (...) {  // out of memory for a line of text: the verb will say so, not this thread
        }
      }
    }
  }

  // A line for the time since the last phase ended (plain and json only).
  void show_gap(Clock::time_point now) {
    last_line_ = now;
    const double elapsed = Seconds(now - ended_at_).count();
    const std::string after(phase_);
    if (form_ == Form::kJson)
      std::fprintf(stderr,
                   "{\"phase\":\"after %s\",\"done\":0,\"total\":0,\"elapsed_s\":%.2f,"
                   "\"eta_s\":null}\n",
                   after.c_str(), elapsed);
    else
      std::fprintf(stderr, "dynpm %s%sworking after %s… %s\n", verb_.c_str(),
                   verb_.empty() ? ": " : ": ", after.c_str(), duration_text(elapsed).c_str());
    std::fflush(stderr);
  }

  void end_phase(Clock::time_point now) {
    ended_ = true;
    ended_at_ = now;
    if (form_ == Form::kLive)
      clear_live_line();
    else
      show(now);
  }

  void clear_live_line() {
    if (!live_shown_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    live_shown_ = false;
  }

  // The current state as one line of the chosen form.
  void show(Clock::time_point now) {
    last_line_ = now;
    const double elapsed = Seconds(now - start_).count();
    const bool counted = total_ > 1;
    const double rate = elapsed > 0 ? double(done_) / elapsed : 0;
    const bool eta_known = counted && done_ > 0 && rate > 0;
    const double eta = ended_ ? 0 : eta_known ? double(total_ - done_) / rate : -1;
    const double percent = counted ? 100.0 * double(done_) / double(total_) : 0;
    const std::string phase(phase_);
    if (form_ == Form::kJson) {
      char eta_text[32] = "null";
      if (eta >= 0) std::snprintf(eta_text, sizeof eta_text, "%.1f", eta);
      std::fprintf(
          stderr, "{\"phase\":\"%s\",\"done\":%zu,\"total\":%zu,\"elapsed_s\":%.2f,\"eta_s\":%s}\n",
          phase.c_str(), done_, total_, elapsed, eta_text);
    } else if (form_ == Form::kPlain) {
      const std::string who = "dynpm " + verb_ + (verb_.empty() ? ": " : ": ");
      if (ended_ && counted)
        std::fprintf(stderr, "%s%s done: %zu in %s (%s)\n", who.c_str(), phase.c_str(), done_,
                     duration_text(elapsed).c_str(), rate_text(rate).c_str());
      else if (ended_)
        std::fprintf(stderr, "%s%s done in %s\n", who.c_str(), phase.c_str(),
                     duration_text(elapsed).c_str());
      else if (counted)
        std::fprintf(stderr, "%s%s %.0f%% (%zu/%zu), %s, %s\n", who.c_str(), phase.c_str(), percent,
                     done_, total_, rate_text(rate).c_str(),
                     eta >= 0 ? (duration_text(eta) + " left").c_str() : "time left unknown");
      else
        std::fprintf(stderr, "%s%s… %s\n", who.c_str(), phase.c_str(),
                     duration_text(elapsed).c_str());
    } else {
      if (counted)
        std::fprintf(stderr, "\r%s %3.0f%%  %zu/%zu  %s  %s\033[K", phase.c_str(), percent, done_,
                     total_, rate_text(rate).c_str(),
                     eta >= 0 ? (duration_text(eta) + " left").c_str() : "");
      else
        std::fprintf(stderr, "\r%s… %s\033[K", phase.c_str(), duration_text(elapsed).c_str());
      live_shown_ = true;
    }
    std::fflush(stderr);
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread ticker_;
  bool stop_ = false;
  Form form_ = ::isatty(STDERR_FILENO) ? Form::kLive : Form::kPlain;
  std::string verb_;
  std::string phase_;
  Clock::time_point start_, last_line_, ended_at_;
  size_t done_ = 0, total_ = 0;
  bool ended_ = true;
  bool live_shown_ = false;
};

Reporter& reporter() {
  static Reporter r;
  return r;
}

}  // namespace

Status configure_progress(const Args& args, const std::string& verb) {
  Form form = ::isatty(STDERR_FILENO) ? Form::kLive : Form::kPlain;
  if (auto v = args.value("--progress")) {
    if (*v == "plain")
      form = Form::kPlain;
    else if (*v == "json")
      form = Form::kJson;
    else if (*v == "none")
      form = Form::kNone;
    else if (*v != "auto")
      return Status::error("--progress takes auto, plain, json or none, got " + quoted_value(*v));
  }
  if (args.has("--quiet")) form = Form::kNone;
  reporter().configure(form, verb);
  return {};
}

void progress(std::string_view phase, size_t done, size_t total) {
  reporter().update(phase, done, total);
}

void clear_progress_line() { reporter().clear_line(); }

void progress_remark(const std::string& text, const std::string& json) {
  reporter().remark(text, json);
}

}  // namespace dynpm::cli
