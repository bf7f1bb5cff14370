// SPDX-License-Identifier: GPL-2.0-or-later
// Spawning a program with its output captured (include/mbsc/run/process.hpp).
#include "mbsc/run/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace mbsc::run {

ProcessResult run_process(const std::vector<std::string>& args, const std::string& input, double timeout_seconds) {
  ProcessResult r;
  int out[2], in[2], err_pipe[2];
  if (pipe2(out, O_CLOEXEC) != 0 || pipe2(in, O_CLOEXEC) != 0 || pipe2(err_pipe, O_CLOEXEC) != 0) {
    r.exit_code = 127;
    r.spawn_error = std::strerror(errno);
    return r;
  }
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // The child: dies with mbsc (a killed mbsc leaves no compiler behind), in its own
    // process group (so a timeout can stop whatever it started), stdin/stdout/stderr on
    // the pipes. An exec failure is reported through err_pipe.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    setpgid(0, 0);
    dup2(in[0], 0);
    dup2(out[1], 1);
    dup2(out[1], 2);
    execvp(argv[0], argv.data());
    const int e = errno;
    if (write(err_pipe[1], &e, sizeof e) < 0) _exit(127);
    _exit(127);
  }
  close(in[0]);
  close(out[1]);
  close(err_pipe[1]);
  if (pid < 0) {
    close(in[1]), close(out[0]), close(err_pipe[0]);
    r.exit_code = 127;
    r.spawn_error = std::string("cannot be started: ") + std::strerror(errno);
    return r;
  }
  int exec_errno = 0;
  const bool exec_failed = read(err_pipe[0], &exec_errno, sizeof exec_errno) == sizeof exec_errno;
  close(err_pipe[0]);
  // Feed the input and drain the output together (either may fill its pipe), until the
  // program closes its output or the time is up.
  struct sigaction ignore {}, old {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ignore, &old);
  std::size_t written = 0;
  if (input.empty() || exec_failed) close(in[1]), in[1] = -1;
  const auto start = std::chrono::steady_clock::now();
  char buf[4096];
  while (!exec_failed) {
    const double left = timeout_seconds - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (timeout_seconds > 0 && left <= 0) {
      r.timed_out = true;
      break;
    }
    pollfd fds[2] = {{out[0], POLLIN, 0}, {in[1], POLLOUT, 0}};
    const int wait_ms = timeout_seconds > 0 ? static_cast<int>(std::min(left, 1.0) * 1000) + 1 : 1000;
    const int n = poll(fds, in[1] >= 0 ? 2 : 1, wait_ms);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    if (in[1] >= 0 && (fds[1].revents & (POLLOUT | POLLERR | POLLHUP))) {
      const ssize_t w = write(in[1], input.data() + written, input.size() - written);
      if (w > 0) written += static_cast<std::size_t>(w);
      if (w < 0 || written == input.size()) close(in[1]), in[1] = -1;
    }
    if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      const ssize_t got = read(out[0], buf, sizeof buf);
      if (got > 0) r.output.append(buf, static_cast<std::size_t>(got));
      else if (got == 0 || errno != EINTR) break;
    }
  }
  if (r.timed_out) {
    kill(-pid, SIGKILL);
    kill(pid, SIGKILL);
  }
  if (in[1] >= 0) close(in[1]);
  close(out[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  sigaction(SIGPIPE, &old, nullptr);
  if (exec_failed) {
    r.exit_code = 127;
    r.spawn_error = std::string("cannot be started: ") + std::strerror(exec_errno);
    return r;
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return r;
}

}  // namespace mbsc::run
