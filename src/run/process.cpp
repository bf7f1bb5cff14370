// SPDX-License-Identifier: GPL-2.0-or-later
// Spawning a program with its output captured (include/mbsc/run/process.hpp).
#include "mbsc/run/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

extern char** environ;

namespace mbsc::run {

ProcessResult run_process(const std::vector<std::string>& args, const std::string& input) {
  ProcessResult r;
  int out[2], in[2];
  if (pipe(out) != 0) {
    r.exit_code = 127;
    r.spawn_error = std::strerror(errno);
    return r;
  }
  if (pipe(in) != 0) {
    close(out[0]), close(out[1]);
    r.exit_code = 127;
    r.spawn_error = std::strerror(errno);
    return r;
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], 0);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_adddup2(&fa, out[1], 2);
  posix_spawn_file_actions_addclose(&fa, in[1]);
  posix_spawn_file_actions_addclose(&fa, out[0]);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  close(in[0]);
  close(out[1]);
  if (rc != 0) {
    close(in[1]), close(out[0]);
    r.exit_code = 127;
    r.spawn_error = std::string("cannot be started: ") + std::strerror(rc);
    return r;
  }
  // Feed the input and drain the output together (either may fill its pipe).
  signal(SIGPIPE, SIG_IGN);
  std::size_t written = 0;
  if (input.empty()) close(in[1]), in[1] = -1;
  char buf[4096];
  for (;;) {
    pollfd fds[2] = {{out[0], POLLIN, 0}, {in[1], POLLOUT, 0}};
    const int n = poll(fds, in[1] >= 0 ? 2 : 1, -1);
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
  if (in[1] >= 0) close(in[1]);
  close(out[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  if (r.exit_code == 127 && r.output.empty()) r.spawn_error = "not found";
  return r;
}

}  // namespace mbsc::run
