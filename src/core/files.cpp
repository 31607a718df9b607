// Whole-file reads with clear errors, and atomic writes (temporary name, fsync, rename).
#include "dynpm/core.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <unordered_map>
#include <utility>

namespace dynpm {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

Result<FilePtr> open_for_reading(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return Status::error(path + ": is a directory, not a file");
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) return Status::error(path + ": cannot open: " + std::strerror(errno));
  return f;
}

}  // namespace

Result<std::string> read_file(const std::string& path) {
  auto f = open_for_reading(path);
  if (!f) return f.status();
  std::string bytes;
  if (std::fseek(f->get(), 0, SEEK_END) == 0) {
    const long size = std::ftell(f->get());
    if (size > 0) bytes.reserve(static_cast<size_t>(size));
    std::rewind(f->get());
  }
  char buffer[1 << 16];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f->get())) > 0) bytes.append(buffer, n);
  if (std::ferror(f->get())) return Status::error(path + ": read failed: " + std::strerror(errno));
  return bytes;
}

Result<MappedFile> MappedFile::open(const std::string& path) {
  auto f = open_for_reading(path);
  if (!f) return f.status();
  struct stat st {};
  if (fstat(fileno(f->get()), &st) != 0)
    return Status::error(path + ": cannot read its size: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return Status::error(path + ": is not a regular file");
  MappedFile m;
  m.size_ = static_cast<size_t>(st.st_size);
  if (m.size_ == 0) return m;
  void* data = mmap(nullptr, m.size_, PROT_READ, MAP_PRIVATE, fileno(f->get()), 0);
  if (data == MAP_FAILED) return Status::error(path + ": cannot map: " + std::strerror(errno));
  m.data_ = data;
  return m;
}

MappedFile::MappedFile(MappedFile&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)) {}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
  if (this != &other) {
    if (data_) munmap(data_, size_);
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

MappedFile::~MappedFile() {
  if (data_) munmap(data_, size_);
}

Result<std::string> read_file_head(const std::string& path, size_t n) {
  auto f = open_for_reading(path);
  if (!f) return f.status();
  std::string bytes(n, '\0');
  bytes.resize(std::fread(bytes.data(), 1, n, f->get()));
  if (std::ferror(f->get())) return Status::error(path + ": read failed: " + std::strerror(errno));
  return bytes;
}

namespace {

// The process id in `name` if it is one of target's temporary names: "<target>.tmp-<pid>-<n>"
// (write_file_atomically), "<stem>.tmp-<pid><ext>" (a staged output) or the staged output's own
// "<stem>.tmp-<pid><ext>.tmp-<pid>-<n>"; -1 otherwise.
long temporary_owner(const std::string& name, const std::filesystem::path& target) {
  auto digits = [&](size_t& at) {
    const size_t begin = at;
    while (at < name.size() && at - begin < 10 && name[at] >= '0' && name[at] <= '9') ++at;
    return at > begin && at - begin < 10 ? std::stol(name.substr(begin, at - begin)) : -1L;
  };
  // ".tmp-<pid>-<n>" from `at` to the end of the name.
  auto atomic_suffix = [&](size_t at) {
    if (name.compare(at, 5, ".tmp-") != 0) return -1L;
    at += 5;
    const long pid = digits(at);
    if (pid < 0 || at >= name.size() || name[at] != '-') return -1L;
    ++at;
    return digits(at) >= 0 && at == name.size() ? pid : -1L;
  };
  const std::string file = target.filename().string(), stem = target.stem().string(),
                    extension = target.extension().string();
  if (name.rfind(file + ".tmp-", 0) == 0) return atomic_suffix(file.size());
  if (name.rfind(stem + ".tmp-", 0) != 0) return -1;
  size_t at = stem.size() + 5;
  const long pid = digits(at);
  if (pid < 0 || name.compare(at, extension.size(), extension) != 0) return -1;
  at += extension.size();
  return at == name.size() || atomic_suffix(at) >= 0 ? pid : -1;
}

}  // namespace

namespace {
std::atomic<size_t> folder_scans{0};
}  // namespace

size_t stale_temporary_scans() { return folder_scans; }

bool process_has_ended(long pid) {
  return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

size_t remove_stale_temporaries(std::span<const std::string> paths) {
  namespace fs = std::filesystem;
  // The targets by folder, and in each folder by the two names a temporary starts with (the
  // file's name and its stem), so that each folder is listed once however many targets it holds.
  struct Folder {
    std::unordered_multimap<std::string, fs::path> by_prefix;
  };
  std::map<fs::path, Folder> folders;
  for (const std::string& path : paths) {
    const fs::path target(path);
    fs::path folder = target.parent_path();
    if (folder.empty()) folder = ".";
    Folder& f = folders[folder];
    f.by_prefix.emplace(target.filename().string(), target);
    if (target.stem() != target.filename()) f.by_prefix.emplace(target.stem().string(), target);
  }
  const auto old_enough = fs::file_time_type::clock::now() - std::chrono::minutes(1);
  const long self = ::getpid();
  size_t removed = 0;
  for (const auto& [folder, f] : folders) {
    ++folder_scans;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      // Every ".tmp-" in the name may end a target's name or stem.
      long owner = -1;
      for (size_t at = name.find(".tmp-"); at != std::string::npos && owner < 0;
           at = name.find(".tmp-", at + 1)) {
        const auto [first, last] = f.by_prefix.equal_range(name.substr(0, at));
        for (auto t = first; t != last && owner < 0; ++t) owner = temporary_owner(name, t->second);
      }
      if (owner <= 0 || owner == self || !process_has_ended(owner)) continue;
      std::error_code file_ec;
      if (!it->is_regular_file(file_ec) || it->last_write_time(file_ec) > old_enough || file_ec)
        continue;
      if (fs::remove(it->path(), file_ec)) ++removed;
    }
  }
  return removed;
}

size_t remove_stale_temporaries(const std::string& path) {
  return remove_stale_temporaries(std::span<const std::string>(&path, 1));
}

namespace {

// A staged file of this process ("<stem>.tmp-<pid><ext>"): its own leftovers are its target's
// too, removed by the one scan for all of a multi-file output's targets, and its folder is
// synced once when the output is committed.
bool is_own_temporary(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  const std::string mark = ".tmp-" + std::to_string(::getpid());
  for (size_t at = name.find(mark); at != std::string::npos; at = name.find(mark, at + 1)) {
    const size_t after = at + mark.size();
    if (after == name.size() || !std::isdigit(static_cast<unsigned char>(name[after]))) return true;
  }
  return false;
}

}  // namespace

Status write_file_atomically(const std::string& path, std::string_view bytes) {
  // A staged file is renamed to its target later, and that rename is what must be durable.
  const bool staged = is_own_temporary(path);
  if (!staged) remove_stale_temporaries(path);
  static std::atomic<unsigned> counter{0};
  const std::string temp =
      path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  {
    FilePtr f(std::fopen(temp.c_str(), "wb"));
    if (!f) return Status::error(path + ": cannot write: " + std::strerror(errno));
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f.get()) == bytes.size() &&
                         std::fflush(f.get()) == 0 && ::fsync(::fileno(f.get())) == 0;
    if (!written) {
      const std::string cause = std::strerror(errno);
      f.reset();
      std::remove(temp.c_str());
      return Status::error(path + ": write failed: " + cause);
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string cause = std::strerror(errno);
    std::remove(temp.c_str());
    return Status::error(path + ": cannot rename the finished file into place: " + cause);
  }
  if (!staged) sync_directory_of(path);
  return {};
}

// Without this the rename itself may be lost in a power cut, leaving the old file or none.
// Best effort: some file systems cannot sync a directory, and the file is complete either way.
void sync_directory_of(const std::string& path) {
  std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) folder = ".";
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace dynpm
