// A reader in a forked child process (contained_read.h): the wire format, the child's loop and
// the parent's proxy FrameSource.
//
// Every message either way is  tag (1 byte)  size (8 bytes, native order)  payload. The payloads
// are flat arrays written and read by Packer / Unpacker below; both ends are this binary.
#include "contained_read.h"

#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <type_traits>

#include "dynpm/sanitizers.h"

namespace dynpm::io {
namespace {

// How long the parent waits for any answer before it takes the child for hung: no answer needs
// more than reading the whole file, so a floor plus the file at a slow disk's (or network
// file system's) pace. A damaged HDF5 file can make libhdf5 loop for ever: a 40 KB one that the
// fuzzer found was refused after a flat 120 s before, after 10 s now.
constexpr int kSilenceFloorSeconds = 10;
constexpr uint64_t kSlowestReadBytesPerSecond = uint64_t{8} << 20;

int silence_seconds(const std::string& path) {
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  const uint64_t read = error ? 0 : uint64_t{size} / kSlowestReadBytesPerSecond;
  return static_cast<int>(std::min<uint64_t>(kSilenceFloorSeconds + read, 1'000'000));
}
// An answer larger than this is a broken child, not a mesh.
constexpr uint64_t kMaxMessage = uint64_t{1} << 38;

// Flat encoding of numbers, arrays of trivially copyable values and strings.
class Packer {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <typename T>
  void put(const std::vector<T>& values) {
    put(uint64_t{values.size()});
    if (!values.empty())
      bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put(const std::string& s) {
    put(uint64_t{s.size()});
    bytes_.append(s);
  }
  void put(const std::vector<std::string>& strings) {
    put(uint64_t{strings.size()});
    for (const std::string& s : strings) put(s);
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

// The reverse of Packer; every get checks the bytes left, false once anything was short.
class Unpacker {
 public:
  explicit Unpacker(std::string_view bytes) : bytes_(bytes) {}
  bool ok() const { return ok_; }
  bool done() const { return ok_ && at_ == bytes_.size(); }

  template <typename T>
  bool get(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (!take(sizeof(T))) return false;
    std::memcpy(&value, bytes_.data() + at_ - sizeof(T), sizeof(T));
    return true;
  }
  template <typename T>
  bool get(std::vector<T>& values) {
    uint64_t n = 0;
    if (!get(n) || n > (bytes_.size() - at_) / sizeof(T) || !take(n * sizeof(T))) return fail();
    values.resize(n);
    if (n > 0) std::memcpy(values.data(), bytes_.data() + at_ - n * sizeof(T), n * sizeof(T));
    return true;
  }
  bool get(std::string& s) {
    uint64_t n = 0;
    if (!get(n) || !take(n)) return fail();
    s.assign(bytes_.data() + at_ - n, n);
    return true;
  }
  bool get(std::vector<std::string>& strings) {
    uint64_t n = 0;
    if (!get(n) || n > bytes_.size() - at_) return fail();
    strings.resize(n);
    for (std::string& s : strings)
      if (!get(s)) return false;
    return true;
  }

 private:
  bool fail() { return ok_ = false; }
  bool take(uint64_t n) {
    if (!ok_ || n > bytes_.size() - at_) return fail();
    at_ += n;
    return true;
  }
  std::string_view bytes_;
  size_t at_ = 0;
  bool ok_ = true;
};

// Writes all of `bytes`; false if the other end is gone (never SIGPIPE: MSG_NOSIGNAL).
bool send_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

bool send_message(int fd, char tag, std::string_view payload) {
  char header[9];
  header[0] = tag;
  const uint64_t size = payload.size();
  std::memcpy(header + 1, &size, 8);
  return send_all(fd, std::string_view(header, 9)) && send_all(fd, payload);
}

enum class Received { kOk, kClosed, kSilent, kMalformed };

// Reads exactly `size` bytes, waiting at most `timeout_ms` for each piece when timeout_ms ≥ 0.
Received receive_all(int fd, char* out, size_t size, int timeout_ms) {
  while (size > 0) {
    if (timeout_ms >= 0) {
      pollfd p{fd, POLLIN, 0};
      const int ready = ::poll(&p, 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) return Received::kSilent;
      if (ready < 0) return Received::kClosed;
    }
    const ssize_t n = ::recv(fd, out, size, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Received::kClosed;
    out += n;
    size -= static_cast<size_t>(n);
  }
  return Received::kOk;
}

Received receive_message(int fd, char& tag, std::string& payload, int timeout_ms) {
  char header[9];
  if (Received r = receive_all(fd, header, 9, timeout_ms); r != Received::kOk) return r;
  tag = header[0];
  uint64_t size = 0;
  std::memcpy(&size, header + 1, 8);
  if (size > kMaxMessage) return Received::kMalformed;
  payload.resize(size);
  return receive_all(fd, payload.data(), size, timeout_ms);
}

// ---------------------------------------------------------------------------------------------
// The child

// What a dying child should do: die by its signal, plainly. Sanitizers and libFuzzer install
// handlers for these that would report the library's crash as ours (and write fuzzer artifacts);
// our own code's sanitizer reports do not go through signals and still show.
void restore_crash_signals() {
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP}) ::signal(sig, SIG_DFL);
}

// A damaged file must not take the machine's memory or leave a core dump: the kernel's OOM
// killer is told to pick the child first, and without sanitizers (which reserve terabytes of
// address space) the child's address space is capped at the machine's memory.
void limit_resources() {
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  std::ofstream("/proc/self/oom_score_adj") << 1000;
  if (kAddressSanitizer) return;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return;
  rlimit as{};
  if (::getrlimit(RLIMIT_AS, &as) != 0) return;
  const rlim_t memory = static_cast<rlim_t>(pages) * static_cast<rlim_t>(page_size);
  if (as.rlim_cur == RLIM_INFINITY || as.rlim_cur > memory) {
    as.rlim_cur = memory;
    ::setrlimit(RLIMIT_AS, &as);
  }
}

Packer pack_opened(const AnimationStream& stream, const std::vector<std::string>& warnings) {
  Packer out;
  const Topology& topology = stream.topology;
  const FrameSource& frames = *stream.frames;
  out.put(warnings);
  out.put(stream.warnings);
  out.put(topology.vertex_count);
  out.put(topology.faces);
  out.put(topology.part_ids);
  out.put(topology.element_ids);
  out.put(topology.node_ids);
  std::vector<int32_t> named_ids;
  std::vector<std::string> part_names;
  for (const PartName& p : topology.part_names) {
    named_ids.push_back(p.id);
    part_names.push_back(p.name);
  }
  out.put(named_ids);
  out.put(part_names);
  out.put(frames.vertex_count());
  std::vector<double> times(frames.step_count());
  std::vector<uint64_t> float_counts(frames.step_count());
  for (size_t t = 0; t < times.size(); ++t) {
    times[t] = frames.step_time(t);
    float_counts[t] = frames.step_float_count(t);
  }
  out.put(times);
  out.put(float_counts);
  std::vector<std::string> units;
  std::vector<uint8_t> locations;
  for (const FieldInfo& field : frames.fields()) {
    units.push_back(field.unit);
    locations.push_back(static_cast<uint8_t>(field.location));
  }
  out.put(frames.field_names());
  out.put(units);
  out.put(locations);
  return out;
}

// Answers step and field requests until the parent closes its end.
void serve(int fd, const FrameSource& frames, size_t face_count) {
  const std::vector<FieldInfo> fields = frames.fields();
  std::vector<float> values;
  char tag = 0;
  std::string request;
  while (receive_message(fd, tag, request, -1) == Received::kOk) {
    uint64_t field = 0, t = 0;
    Unpacker in(request);
    const bool step = tag == 'S';
    if (!in.get(field) || !in.get(t) || !in.done() || t >= frames.step_count() ||
        (!step && field >= fields.size())) {
      if (!send_message(fd, 'E', "bad request to the reader's process")) return;
      continue;
    }
    const bool per_face = !step && fields[field].location == FieldLocation::kElement;
    values.assign(step       ? frames.step_float_count(t)
                  : per_face ? face_count
                             : frames.vertex_count(),
                  0.0f);
    const Status status = step ? frames.read_step(t, values) : frames.read_field(field, t, values);
    const bool sent =
        status.ok() ? send_message(fd, 'D',
                                   std::string_view(reinterpret_cast<const char*>(values.data()),
                                                    values.size() * sizeof(float)))
                    : send_message(fd, 'E', status.message());
    if (!sent) return;
  }
}

[[noreturn]] void run_child(
    int fd, const ReadOptions& options,
    const std::function<Result<AnimationStream>(const ReadOptions&)>& open) {
  restore_crash_signals();
  limit_resources();
  try {
    std::vector<std::string> warnings;
    ReadOptions child_options = options;  // every option but where the notes go
    child_options.warn = [&warnings](const std::string& w) { warnings.push_back(w); };
    Result<AnimationStream> stream = open(child_options);
    if (!stream.ok()) {
      send_message(fd, 'E', stream.status().message());
    } else if (send_message(fd, 'O', pack_opened(*stream, warnings).bytes())) {
      serve(fd, *stream->frames, stream->topology.face_count());
    }
  } catch (const std::exception& e) {
    send_message(fd, 'E', std::string("the reader failed: ") + e.what());
  }
  // _exit: no atexit handlers, no stdio flush of the parent's buffers, no leak check of what
  // the library still holds.
  ::_exit(0);
}

// ---------------------------------------------------------------------------------------------
// The parent

// The child process and the parent's end of the socket; killed and reaped when let go.
class Child {
 public:
  Child(pid_t pid, int fd, std::string path, const char* library)
      : pid_(pid),
        fd_(fd),
        path_(std::move(path)),
        library_(library),
        silence_seconds_(silence_seconds(path_)) {}
  ~Child() {
    ::close(fd_);
    if (pid_ > 0) reap();
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // Sends a request and receives its answer.
  Status ask(char tag, std::string_view payload, char& answer, std::string& reply) {
    if (dead_.ok() && !send_message(fd_, tag, payload)) return died(Received::kClosed);
    return receive(answer, reply);
  }
  // Receives the next answer; a dead, silent or garbled child is an error, now and later.
  Status receive(char& answer, std::string& reply) {
    if (!dead_.ok()) return dead_;
    const Received r = receive_message(fd_, answer, reply, silence_seconds_ * 1000);
    if (r != Received::kOk) return died(r);
    if (answer == 'E') return Status::error(reply);
    return {};
  }

 private:
  // Kills the child, if it still lives, and collects its status. A child that closed the socket
  // by dying is past the point where SIGKILL changes its status.
  int reap() {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    return status;
  }
  Status died(Received how) {
    const int status = reap();
    std::string why;
    if (how == Received::kSilent)
      why = "gave no answer in " + std::to_string(silence_seconds_) + " s";
    else if (how == Received::kMalformed)
      why = "sent a malformed answer";
    else if (WIFSIGNALED(status))
      why = std::string("crashed reading it: ") + ::strsignal(WTERMSIG(status));
    else if (WIFEXITED(status) && WEXITSTATUS(status) != 0)
      why = "crashed reading it: exit status " + std::to_string(WEXITSTATUS(status));
    else
      why = "stopped reading it";
    dead_ = Status::error(path_ + ": damaged " + library_ + " file (the " + library_ + " library " +
                          why + ")");
    return dead_;
  }

  pid_t pid_;
  int fd_;
  std::string path_;
  std::string library_;
  int silence_seconds_;
  Status dead_;
};

// The parent's FrameSource: every read is a request to the child.
class ChildFrames final : public FrameSource {
 public:
  ChildFrames(std::unique_ptr<Child> child, uint32_t vertex_count, std::vector<double> times,
              std::vector<uint64_t> float_counts, std::vector<FieldInfo> fields)
      : child_(std::move(child)),
        vertex_count_(vertex_count),
        times_(std::move(times)),
        float_counts_(std::move(float_counts)),
        fields_(std::move(fields)) {}

  uint32_t vertex_count() const override { return vertex_count_; }
  size_t step_count() const override { return times_.size(); }
  double step_time(size_t t) const override { return times_[t]; }
  size_t step_float_count(size_t t) const override { return float_counts_[t]; }
  std::vector<FieldInfo> fields() const override { return fields_; }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < step_count() && out.size() == step_float_count(t));
    return request('S', 0, t, out);
  }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < fields_.size() && t < step_count());
    return request('F', field, t, out);
  }

 private:
  Status request(char tag, uint64_t field, uint64_t t, std::span<float> out) const {
    const std::lock_guard lock(mutex_);  // one conversation at a time on the socket
    Packer in;
    in.put(field);
    in.put(t);
    char answer = 0;
    DYNPM_RETURN_IF_ERROR(child_->ask(tag, in.bytes(), answer, reply_));
    if (answer != 'D' || reply_.size() != out.size_bytes())
      return Status::error("the reader's process answered " + std::to_string(reply_.size()) +
                           " bytes for " + std::to_string(out.size()) + " values");
    if (!out.empty()) std::memcpy(out.data(), reply_.data(), reply_.size());
    return {};
  }

  std::unique_ptr<Child> child_;
  uint32_t vertex_count_;
  std::vector<double> times_;
  std::vector<uint64_t> float_counts_;
  std::vector<FieldInfo> fields_;
  mutable std::mutex mutex_;
  mutable std::string reply_;
};

}  // namespace

Result<AnimationStream> open_in_child(
    const std::string& path, const ReadOptions& options, const char* library,
    const std::function<Result<AnimationStream>(const ReadOptions&)>& open) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    return Status::error(path + ": cannot start the reader's process: " + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    return Status::error(path + ": cannot start the reader's process: " + std::strerror(error));
  }
  if (pid == 0) {
    ::close(fds[0]);
    // The child must not outlive dynpm (it would wait on a socket no one holds).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(0);
    run_child(fds[1], options, open);
  }
  ::close(fds[1]);
  auto child = std::make_unique<Child>(pid, fds[0], path, library);

  char answer = 0;
  std::string reply;
  DYNPM_RETURN_IF_ERROR(child->receive(answer, reply));
  std::vector<std::string> warnings;
  AnimationStream stream;
  Topology& topology = stream.topology;
  uint32_t vertex_count = 0;
  std::vector<double> times;
  std::vector<uint64_t> float_counts;
  std::vector<std::string> names, units;
  std::vector<uint8_t> locations;
  std::vector<int32_t> named_ids;
  std::vector<std::string> part_names;
  Unpacker in(reply);
  in.get(warnings);
  in.get(stream.warnings);
  in.get(topology.vertex_count);
  in.get(topology.faces);
  in.get(topology.part_ids);
  in.get(topology.element_ids);
  in.get(topology.node_ids);
  in.get(named_ids);
  in.get(part_names);
  in.get(vertex_count);
  in.get(times);
  in.get(float_counts);
  in.get(names);
  in.get(units);
  in.get(locations);
  if (answer != 'O' || !in.done() || float_counts.size() != times.size() ||
      units.size() != names.size() || locations.size() != names.size() ||
      part_names.size() != named_ids.size())
    return Status::error(path + ": the reader's process sent a malformed answer");
  for (size_t p = 0; p < named_ids.size(); ++p) topology.set_part_name(named_ids[p], part_names[p]);
  if (options.warn)
    for (const std::string& w : warnings) options.warn(w);
  std::vector<FieldInfo> fields;
  for (size_t f = 0; f < names.size(); ++f) {
    if (locations[f] > 1)
      return Status::error(path + ": the reader's process sent a malformed answer");
    fields.push_back({names[f], static_cast<FieldLocation>(locations[f]), units[f]});
  }
  stream.frames = std::make_unique<ChildFrames>(std::move(child), vertex_count, std::move(times),
                                                std::move(float_counts), std::move(fields));
  return stream;
}

}  // namespace dynpm::io
