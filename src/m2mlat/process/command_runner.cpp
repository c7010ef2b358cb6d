// ProcessRunner: posix_spawnp with the child's stdout and stderr on pipes, read with poll() until
// both close or the deadline passes. No shell is involved, so arguments need no quoting.
#include "m2mlat/process/command_runner.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/printable.hpp"

extern char** environ;

namespace m2mlat::process {

namespace {

// 0 if `program` names an executable file (as posix_spawnp would find it: a path if it has a slash,
// else the first match in $PATH), else the errno why not. posix_spawnp reports the same, but only
// where the child can hand the exec's failure back (not under an emulator that turns vfork into
// fork, such as QEMU's user mode): checking first makes "not started" mean the same everywhere.
int not_executable(const std::string& program) {
  if (program.find('/') != std::string::npos) return ::access(program.c_str(), X_OK) == 0 ? 0 : errno;
  const char* env = std::getenv("PATH");
  const std::string path = env != nullptr ? env : "/usr/local/bin:/usr/bin:/bin";
  int why = ENOENT;
  for (std::size_t start = 0; start <= path.size();) {
    const auto end = std::min(path.find(':', start), path.size());
    const std::string dir = end > start ? path.substr(start, end - start) : ".";
    if (::access((dir + "/" + program).c_str(), X_OK) == 0) return 0;
    if (errno == EACCES) why = EACCES;  // found but not executable: say so, as execvp does
    start = end + 1;
  }
  return why;
}

}  // namespace

std::string command_line(const std::vector<std::string>& argv) {
  std::string out;
  for (const auto& arg : argv) {
    if (!out.empty()) out += ' ';
    if (arg.empty() || arg.find_first_of(" \t'\"") != std::string::npos)
      out += "'" + arg + "'";
    else
      out += arg;
  }
  return out;
}

CommandResult ProcessRunner::run(const std::vector<std::string>& argv, core::Duration timeout) {
  CommandResult result;
  if (argv.empty()) {
    result.err = "no command";
    return result;
  }
  if (const int why = not_executable(argv[0]); why != 0) {
    result.err = argv[0] + ": " + std::strerror(why);
    return result;
  }
  std::array<int, 2> out_pipe{-1, -1};
  std::array<int, 2> err_pipe{-1, -1};
  if (::pipe2(out_pipe.data(), O_CLOEXEC) != 0) {
    result.err = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  core::Fd out_read(out_pipe[0]), out_write(out_pipe[1]);
  if (::pipe2(err_pipe.data(), O_CLOEXEC) != 0) {
    result.err = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  core::Fd err_read(err_pipe[0]), err_write(err_pipe[1]);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_write.get(), 1);
  posix_spawn_file_actions_adddup2(&actions, err_write.get(), 2);

  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  out_write.reset();
  err_write.reset();
  if (rc != 0) {
    result.err = argv[0] + ": " + std::strerror(rc);
    return result;
  }
  result.started = true;

  const std::int64_t deadline = core::now_ns(CLOCK_MONOTONIC) + timeout.count();
  std::array<char, 4096> buffer{};
  while (out_read || err_read) {
    const std::int64_t left_ns = deadline - core::now_ns(CLOCK_MONOTONIC);
    if (left_ns <= 0) {
      result.timed_out = true;
      break;
    }
    std::array<pollfd, 2> fds{pollfd{out_read.get(), POLLIN, 0}, pollfd{err_read.get(), POLLIN, 0}};
    const int n = ::poll(fds.data(), fds.size(), static_cast<int>(left_ns / 1'000'000 + 1));
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      core::Fd& fd = i == 0 ? out_read : err_read;
      std::string& sink = i == 0 ? result.out : result.err;
      const ssize_t got = ::read(fd.get(), buffer.data(), buffer.size());
      if (got > 0)
        sink.append(buffer.data(), static_cast<std::size_t>(got));
      else if (got == 0 || errno != EINTR)
        fd.reset();
    }
  }
  // Both pipes closed (or the deadline passed): wait for the exit, still within the deadline.
  int status = 0;
  while (!result.timed_out) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid || (done < 0 && errno != EINTR)) break;
    if (core::now_ns(CLOCK_MONOTONIC) >= deadline) {
      result.timed_out = true;
      break;
    }
    const timespec pause{0, 1'000'000};  // 1 ms
    ::nanosleep(&pause, nullptr);
  }
  if (result.timed_out) {
    ::kill(pid, SIGKILL);
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (!result.timed_out && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

std::string failure_text(const CommandResult& result) {
  if (result.ok()) return {};
  if (!result.started) return core::printable(result.err);
  if (result.timed_out) return "timed out";
  std::string_view said = result.err.empty() ? result.out : result.err;
  while (!said.empty() && std::string_view(" \t\r\n").find(said.front()) != std::string_view::npos)
    said.remove_prefix(1);
  while (!said.empty() && std::string_view(" \t\r\n").find(said.back()) != std::string_view::npos)
    said.remove_suffix(1);
  const std::string status = fmt::format("exit status {}", result.exit_code);
  return said.empty() ? status : status + ": " + core::printable(said.substr(0, 300));
}

core::Error command_error(const std::vector<std::string>& argv, const CommandResult& result) {
  return core::Error(core::ErrorKind::io, fmt::format("{}: {}", command_line(argv), failure_text(result)));
}

}  // namespace m2mlat::process
