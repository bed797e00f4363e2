#include "core/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "solvers/base/cleanup.h"
#include "solvers/base/error.h"
#include "core/timer.h"

namespace db {

std::string ChildRun::describe() const {
  if (timed_out) return fmt::format("timed out after {:.1f} s (killed)", wall_s);
  if (term_signal) return fmt::format("signal {} ({})", term_signal, ::strsignal(term_signal));
  return fmt::format("exit {}", exit_code);
}

std::string self_executable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

ChildRun run_child(const std::vector<std::string>& argv, double timeout_s) {
  if (argv.empty()) throw Error("run_child: empty argv");
  // Built before fork: the child may only call async-signal-safe functions until exec.
  std::vector<char*> cargv;
  for (const auto& s : argv) cargv.push_back(const_cast<char*>(s.c_str()));
  cargv.push_back(nullptr);

  int outp[2], errp[2];
  if (::pipe2(outp, O_CLOEXEC) != 0) throw Error(fmt::format("pipe: {}", std::strerror(errno)));
  if (::pipe2(errp, O_CLOEXEC) != 0) {
    ::close(outp[0]);
    ::close(outp[1]);
    throw Error(fmt::format("pipe: {}", std::strerror(errno)));
  }
  Timer wall;
  // An ending signal to this process is forwarded to the child and waits for it (cleanup.h): held back from
  // the fork until the child is registered, so none arrives in between and leaves the child running.
  std::optional<cleanup::ForkGuard> hold(std::in_place);
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (int fd : {outp[0], outp[1], errp[0], errp[1]}) ::close(fd);
    throw Error(fmt::format("fork: {}", std::strerror(errno)));
  }
  if (pid == 0) {
    hold->in_child();
    ::dup2(outp[1], STDOUT_FILENO);  // dup2 clears O_CLOEXEC on the copies
    ::dup2(errp[1], STDERR_FILENO);
    ::execv(cargv[0], cargv.data());
    const char msg[] = "run_child: execv failed\n";
    [[maybe_unused]] ssize_t w = ::write(STDERR_FILENO, msg, sizeof msg - 1);
    ::_exit(127);
  }
  const cleanup::ChildProcess forward_signals(pid);
  hold.reset();
  ::close(outp[1]);
  ::close(errp[1]);

  ChildRun r;
  pollfd fds[2] = {{outp[0], POLLIN, 0}, {errp[0], POLLIN, 0}};
  std::string* sinks[2] = {&r.out, &r.err};
  int open_fds = 2;
  char buf[65536];
  while (open_fds > 0) {
    int wait_ms = -1;
    if (timeout_s > 0) {
      const double left = timeout_s - wall.seconds();
      if (left <= 0) {
        ::kill(pid, SIGKILL);  // the pipes then reach EOF
        r.timed_out = true;
        timeout_s = 0;
        continue;
      }
      wait_ms = static_cast<int>(left * 1000) + 1;
    }
    const int pr = ::poll(fds, 2, wait_ms);
    if (pr < 0 && errno == EINTR) continue;
    if (pr < 0) break;
    for (int k = 0; k < 2; ++k) {
      if (fds[k].fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t got = ::read(fds[k].fd, buf, sizeof buf);
      if (got > 0) {
        sinks[k]->append(buf, static_cast<std::size_t>(got));
      } else if (got == 0 || errno != EINTR) {
        ::close(fds[k].fd);
        fds[k].fd = -1;
        --open_fds;
      }
    }
  }
  for (auto& f : fds)
    if (f.fd >= 0) ::close(f.fd);

  // A child that closed its pipes may still be running: keep honouring the deadline while reaping it.
  int status = 0;
  rusage ru{};
  for (;;) {
    const pid_t w = ::wait4(pid, &status, timeout_s > 0 ? WNOHANG : 0, &ru);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) break;
    if (w == 0) {
      if (wall.seconds() >= timeout_s) {
        ::kill(pid, SIGKILL);
        r.timed_out = true;
        timeout_s = 0;  // now block until it is reaped
      } else {
        ::usleep(10000);
      }
    }
  }
  r.wall_s = wall.seconds();
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.term_signal = WTERMSIG(status);
  r.ru_maxrss_bytes = static_cast<std::size_t>(ru.ru_maxrss) * 1024;  // KiB on Linux
  r.user_s = ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6;
  r.sys_s = ru.ru_stime.tv_sec + ru.ru_stime.tv_usec * 1e-6;
  return r;
}

std::string ChildRun::stderr_tail(std::size_t max_chars) const {
  const std::string& text = err;
  std::string t = text.size() > max_chars ? text.substr(text.size() - max_chars) : text;
  for (char& c : t)
    if (c == '\n' || c == '\r') c = ' ';
  while (!t.empty() && t.back() == ' ') t.pop_back();
  return t;
}

void limit_address_space(std::size_t bytes) {
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer reserves terabytes of shadow address space: any cap would fail its first mmap. The
  // sanitizer build runs cells uncapped (the budget is still checked against the prediction first).
  bytes = 0;
#endif
  if (bytes == 0) return;
  const rlimit lim{bytes, bytes};
  ::setrlimit(RLIMIT_AS, &lim);
}

}  // namespace db
