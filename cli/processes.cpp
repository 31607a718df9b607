#include "processes.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

extern char** environ;

namespace dynpm::cli {
namespace {

std::vector<char*> argv_of(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  return argv;
}

std::string how_it_ended(int status) {
  if (WIFEXITED(status))
    return WEXITSTATUS(status) == 0 ? "" : "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "stopped";
}

// posix_spawnp with stdin from /dev/null and stdout (and stderr unless `keep_stderr`) to `fd`.
Result<pid_t> spawn_with_output(const std::vector<std::string>& args, int fd, bool keep_stderr) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fd, 1);
  if (!keep_stderr) posix_spawn_file_actions_adddup2(&actions, fd, 2);
  posix_spawn_file_actions_addclose(&actions, fd);
  pid_t pid = 0;
  std::vector<char*> argv = argv_of(args);
  const int error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) return Status::error("cannot run " + args[0] + ": " + std::strerror(error));
  return pid;
}

}  // namespace

Result<std::string> own_executable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return Status::error("cannot find the dynpm program (/proc/self/exe): " + ec.message());
  return self.string();
}

Result<pid_t> start_process(const std::vector<std::string>& argv, const std::string& log) {
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return Status::error(log + ": cannot write the log: " + std::strerror(errno));
  auto pid = spawn_with_output(argv, fd, false);
  ::close(fd);
  return pid;
}

Result<Ended> wait_for_any_child() {
  int status = 0;
  pid_t pid;
  do {
    pid = ::waitpid(-1, &status, 0);
  } while (pid < 0 && errno == EINTR);
  if (pid < 0) return Status::error(std::string("waiting for a build: ") + std::strerror(errno));
  return Ended{pid, how_it_ended(status)};
}

Result<std::string> run_and_capture(const std::vector<std::string>& argv) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0)
    return Status::error(std::string("cannot make a pipe: ") + std::strerror(errno));
  auto pid = spawn_with_output(argv, pipe_fds[1], true);
  ::close(pipe_fds[1]);
  std::string out;
  if (pid) {
    char buffer[4096];
    for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) != 0;) {
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) break;
      out.append(buffer, size_t(n));
    }
  }
  ::close(pipe_fds[0]);
  if (!pid) return pid.status();
  int status = 0;
  while (::waitpid(*pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (std::string failure = how_it_ended(status); !failure.empty())
    return Status::error(argv[0] + " failed (" + failure + ")");
  return out;
}

std::string shell_quoted(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace dynpm::cli
