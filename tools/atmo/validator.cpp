#include "validator.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <csignal>

namespace atmo::validate {

namespace {

CheckResult run_isolated(const Check& check, const Options& options) {
  int fds[2];
  if (pipe(fds) != 0) return {false, "pipe() failed"};
  std::fflush(stdout);
  std::fflush(stderr);
  pid_t pid = fork();
  if (pid < 0) return {false, "fork() failed"};
  if (pid == 0) {
    close(fds[0]);
    alarm(static_cast<unsigned>(options.timeout_s));
    CheckResult r;
    try {
      r = check.run(options.plugin_path);
    } catch (const std::exception& e) {
      r = {false, std::string("exception in the validator: ") + e.what()};
    }
    std::string message = r.detail;
    ssize_t ignored = write(fds[1], message.data(), message.size());
    (void)ignored;
    close(fds[1]);
    _exit(r.passed ? 0 : 1);
  }
  close(fds[1]);
  std::string message;
  char buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof(buffer))) > 0) message.append(buffer, static_cast<size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) {
    int sig = WTERMSIG(status);
    return {false, std::string(sig == SIGALRM ? "timed out" : "crashed with signal ") +
                       (sig == SIGALRM ? "" : std::to_string(sig) + " (" + strsignal(sig) + ")") +
                       (message.empty() ? "" : "; " + message)};
  }
  return {WIFEXITED(status) && WEXITSTATUS(status) == 0, message};
}

}  // namespace

int run_validation(const Options& options) {
  int failures = 0, passes = 0;
  for (const Check& check : all_checks()) {
    if (!options.filter.empty() && check.name.find(options.filter) == std::string::npos) continue;
    CheckResult r = options.in_process ? check.run(options.plugin_path) : run_isolated(check, options);
    if (r.passed) {
      ++passes;
      std::printf("PASS %s%s%s\n", check.name.c_str(), r.detail.empty() ? "" : ": ", r.detail.c_str());
    } else {
      ++failures;
      std::printf("FAIL %s: %s\n", check.name.c_str(), r.detail.c_str());
    }
    std::fflush(stdout);
  }
  std::printf("atmo validate: %d passed, %d failed\n", passes, failures);
  return failures;
}

}  // namespace atmo::validate
