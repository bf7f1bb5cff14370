// SPDX-License-Identifier: GPL-2.0-or-later
// Spawning a program with its output captured (include/mbsc/run/process.hpp).
#include "mbsc/run/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace mbsc::run {

namespace {

/// The guardian's handler: mbsc is gone (PR_SET_PDEATHSIG) or the guardian was told to
/// stop: kill the whole group, the guardian included.
void end_group(int) { ::kill(0, SIGKILL); }

/// Writes errno into the pipe that tells mbsc the program could not be started.
[[noreturn]] void report_and_exit(int fd, int error) {
  if (::write(fd, &error, sizeof error) < 0) _exit(127);
  _exit(127);
}

struct Pipe {
  int read = -1, write = -1;
  bool open() {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return false;
    read = fds[0], write = fds[1];
    return true;
  }
  void close_read() {
    if (read >= 0) ::close(read);
    read = -1;
  }
  void close_write() {
    if (write >= 0) ::close(write);
    write = -1;
  }
  void close_both() { close_read(), close_write(); }
};

/// The child side, after fork: becomes the guardian of a new process group, forks the
/// program and waits for it. Only async-signal-safe calls (mbsc has other threads).
[[noreturn]] void guardian(pid_t parent, char* const* argv, const ProcessOptions& o, Pipe& in, Pipe& out, Pipe& err,
                           Pipe& exec_report) {
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) _exit(127);  // mbsc ended before the signal was armed
  ::setpgid(0, 0);
  struct sigaction stop {};
  stop.sa_handler = end_group;
  sigemptyset(&stop.sa_mask);
  for (int s : {SIGTERM, SIGINT, SIGHUP, SIGQUIT}) ::sigaction(s, &stop, nullptr);
  struct sigaction plain {};
  plain.sa_handler = SIG_DFL;
  sigemptyset(&plain.sa_mask);
  ::sigaction(SIGPIPE, &plain, nullptr);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  if (o.memory_mib > 0) {
    const rlim_t bytes = static_cast<rlim_t>(o.memory_mib) << 20;
    const struct rlimit limit {bytes, bytes};
    ::setrlimit(RLIMIT_DATA, &limit);
  }
  const pid_t program = ::fork();
  if (program < 0) report_and_exit(exec_report.write, errno);
  if (program == 0) {
    for (int s : {SIGTERM, SIGINT, SIGHUP, SIGQUIT}) ::sigaction(s, &plain, nullptr);
    if (o.private_files) ::umask(077);
    if (o.working_folder >= 0 && ::fchdir(o.working_folder) != 0) report_and_exit(exec_report.write, errno);
    ::dup2(in.read, 0);
    ::dup2(out.write, 1);
    ::dup2(o.separate_errors ? err.write : out.write, 2);
    ::execvp(argv[0], argv);
    report_and_exit(exec_report.write, errno);
  }
  // The pipes are the program's; the guardian keeps none open (mbsc sees end of file
  // when the program closes its ends).
  in.close_both(), out.close_both(), err.close_both(), exec_report.close_both();
  int status = 0;
  while (::waitpid(program, &status, 0) < 0 && errno == EINTR) {
  }
  _exit(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0));
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& args, const std::string& input, double timeout_seconds) {
  ProcessOptions o;
  o.input = input;
  o.timeout_seconds = timeout_seconds;
  return run_process(args, o);
}

ProcessResult run_process(const std::vector<std::string>& args, const ProcessOptions& o) {
  ProcessResult r;
  Pipe in, out, err, exec_report;
  if (!in.open() || !out.open() || (o.separate_errors && !err.open()) || !exec_report.open()) {
    r.exit_code = 127;
    r.spawn_error = std::strerror(errno);
    in.close_both(), out.close_both(), err.close_both(), exec_report.close_both();
    return r;
  }
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) guardian(parent, argv.data(), o, in, out, err, exec_report);
  in.close_read(), out.close_write(), err.close_write(), exec_report.close_write();
  if (pid < 0) {
    r.exit_code = 127;
    r.spawn_error = std::string("cannot be started: ") + std::strerror(errno);
    in.close_both(), out.close_both(), err.close_both(), exec_report.close_both();
    return r;
  }
  // The report pipe closes when the program has started (close-on-exec) or carries errno.
  int exec_errno = 0;
  ssize_t got_report = 0;
  while ((got_report = ::read(exec_report.read, &exec_errno, sizeof exec_errno)) < 0 && errno == EINTR) {
  }
  const bool exec_failed = got_report == static_cast<ssize_t>(sizeof exec_errno);
  exec_report.close_read();
  // Feed the input and drain the outputs together (any may fill its pipe), until the
  // program closes its outputs or the time is up.
  struct sigaction ignore {}, old {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ignore, &old);
  std::size_t written = 0;
  if (o.input.empty() || exec_failed) in.close_write();
  const auto start = std::chrono::steady_clock::now();
  char buf[65536];
  bool out_open = !exec_failed, err_open = !exec_failed && o.separate_errors;
  while (out_open || err_open) {
    const double left =
        o.timeout_seconds - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.timeout_seconds > 0 && left <= 0) {
      r.timed_out = true;
      break;
    }
    pollfd fds[3] = {{out_open ? out.read : -1, POLLIN, 0}, {err_open ? err.read : -1, POLLIN, 0},
                     {in.write, POLLOUT, 0}};
    const int wait_ms = o.timeout_seconds > 0 ? static_cast<int>(std::min(left, 1.0) * 1000) + 1 : 1000;
    const int n = ::poll(fds, 3, wait_ms);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    if (in.write >= 0 && (fds[2].revents & (POLLOUT | POLLERR | POLLHUP))) {
      const ssize_t w = ::write(in.write, o.input.data() + written, o.input.size() - written);
      if (w > 0) written += static_cast<std::size_t>(w);
      if ((w < 0 && errno != EINTR && errno != EAGAIN) || written == o.input.size()) in.close_write();
    }
    for (int k = 0; k < 2; ++k) {
      if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t got = ::read(fds[k].fd, buf, sizeof buf);
      if (got > 0) (k == 0 ? r.output : r.errors).append(buf, static_cast<std::size_t>(got));
      else if (got == 0 || errno != EINTR) (k == 0 ? out_open : err_open) = false;
    }
  }
  if (r.timed_out) ::kill(-pid, SIGKILL);  // the guardian, the program and all it started
  in.close_write(), out.close_read(), err.close_read();
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  ::kill(-pid, SIGKILL);  // anything the program left running in its group
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
