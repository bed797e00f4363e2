#include "solvers/base/cleanup.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace db::cleanup {
namespace {

// A slot's life: free -> claimed (its fields being written) -> active -> free. The handler reads active slots only.
enum State : int { kFree = 0, kClaimed = 1, kActive = 2 };

struct Scratch {
  std::atomic<int> state{kFree};
  pid_t owner = 0;  // the registering process: a forked copy (before its exec) must not remove its parent's files
  ScratchPath::Matching matching = ScratchPath::Exact;
  char path[4096] = {};
};

struct Child {
  std::atomic<int> state{kFree};
  pid_t owner = 0, pid = 0;
};

constexpr int kScratchSlots = 64, kChildSlots = 16;
Scratch g_scratch[kScratchSlots];
Child g_children[kChildSlots];
std::atomic<int> g_deferring{0}, g_pending{0};
std::atomic<bool> g_acting{false};

// A child that does not end within this after the forwarded signal is killed (SIGKILL).
constexpr long kChildGraceMs = 5000;

// The signals whose default action ends the process and that a user or the system sends to stop a run: a closed
// terminal (SIGHUP), Ctrl-C and Ctrl-\ (SIGINT, SIGQUIT), a reader gone (SIGPIPE), kill and timeout (SIGTERM),
// alarms, user signals and a CPU-time limit. Each cleans up before the process ends by it.
constexpr int kEndingSignals[] = {SIGHUP, SIGINT, SIGQUIT, SIGPIPE, SIGTERM, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU};

sigset_t ending_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : kEndingSignals) sigaddset(&set, sig);
  return set;
}

template <class Slot, std::size_t N>
int claim(Slot (&slots)[N]) {
  install_handlers();
  for (std::size_t i = 0; i < N; ++i) {
    int expected = kFree;
    if (slots[i].state.compare_exchange_strong(expected, kClaimed)) {
      slots[i].owner = ::getpid();
      return int(i);
    }
  }
  return -1;
}

// Below: async-signal-safe only (no allocation, no locks, no stdio).

void sleep_ms(long ms) {
  timespec t{ms / 1000, (ms % 1000) * 1000000L};
  while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
  }
}

// Removes the files of directory `dir` whose names begin with `prefix`. Scans again after removing (a directory
// listing read while entries are removed may skip some) until a scan removes nothing.
void remove_prefixed(const char* dir, const char* prefix) {
  const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  const std::size_t n = std::strlen(prefix);
  alignas(8) char buf[8192];
  for (int pass = 0; pass < 16; ++pass) {
    bool removed = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const long got = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (got <= 0) break;
      for (long at = 0; at < got;) {
        const auto* e = reinterpret_cast<const dirent64*>(buf + at);
        if (std::strncmp(e->d_name, prefix, n) == 0 && ::unlinkat(fd, e->d_name, 0) == 0) removed = true;
        at += e->d_reclen;
      }
    }
    if (!removed) break;
  }
  ::close(fd);
}

void remove_scratch() {
  const pid_t self = ::getpid();
  for (Scratch& s : g_scratch) {
    if (s.state.load() != kActive || s.owner != self) continue;
    if (s.matching == ScratchPath::Exact) {
      ::unlink(s.path);
      continue;
    }
    char dir[sizeof s.path];
    std::memcpy(dir, s.path, sizeof dir);
    char* slash = std::strrchr(dir, '/');
    if (slash == nullptr) {
      remove_prefixed(".", s.path);
    } else {
      *slash = '\0';
      remove_prefixed(slash == dir ? "/" : dir, slash + 1);
    }
  }
}

// Children get SIGINT for a SIGINT and SIGTERM for any other ending signal (a pipe or terminal closed on this
// process is not closed on them), and clean up as this process does.
void end_children(int sig) {
  const pid_t self = ::getpid();
  const int forwarded = sig == SIGINT ? SIGINT : SIGTERM;
  bool mine[kChildSlots] = {};
  for (int i = 0; i < kChildSlots; ++i) {
    mine[i] = g_children[i].state.load() == kActive && g_children[i].owner == self;
    if (mine[i]) ::kill(g_children[i].pid, forwarded);
  }
  for (long waited = 0;; waited += 10) {
    bool running = false;
    for (int i = 0; i < kChildSlots; ++i) {
      if (!mine[i]) continue;
      const pid_t w = ::waitpid(g_children[i].pid, nullptr, WNOHANG);
      if (w == 0 && waited >= kChildGraceMs) {
        ::kill(g_children[i].pid, SIGKILL);
        ::waitpid(g_children[i].pid, nullptr, 0);
        mine[i] = false;
      } else if (w != 0) {
        mine[i] = false;  // reaped, or no longer our child
      } else {
        running = true;
      }
    }
    if (!running) return;
    sleep_ms(10);
  }
}

// Cleans up and ends the process by `sig` (its default action); once, whichever thread gets here first.
void act(int sig) {
  if (g_acting.exchange(true)) return;
  end_children(sig);  // first: a child may write into the registered scratch until it ends
  remove_scratch();
  ::signal(sig, SIG_DFL);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, sig);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  ::raise(sig);
  ::_exit(128 + sig);  // not reached: the default action of an ending signal ends the process
}

void on_signal(int sig) {
  const int saved = errno;
  if (g_deferring.load() > 0) {
    g_pending.store(sig);
    // The last DeferSignals may have ended between the test and the store, without seeing it.
    if (g_deferring.load() > 0) {
      errno = saved;
      return;
    }
  }
  act(sig);
  errno = saved;
}

}  // namespace

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sa.sa_mask = ending_signals();
    sa.sa_flags = SA_RESTART;
    for (int sig : kEndingSignals) {
      struct sigaction old {};
      // A signal ignored when the process started (nohup, a background job of a non-interactive shell) stays so.
      if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      ::sigaction(sig, &sa, nullptr);
    }
    // A file-size limit (ulimit -f) makes the write that passes it fail (EFBIG), reported and cleaned up as a
    // full disk is, instead of ending the process mid-write.
    ::signal(SIGXFSZ, SIG_IGN);
  });
}

ScratchPath::ScratchPath(const std::string& path, Matching matching) {
  slot_ = claim(g_scratch);
  if (slot_ < 0) return;
  Scratch& s = g_scratch[slot_];
  if (path.size() >= sizeof s.path) {  // longer than any path the system takes: nothing to remove
    s.state.store(kFree);
    slot_ = -1;
    return;
  }
  std::memcpy(s.path, path.c_str(), path.size() + 1);
  s.matching = matching;
  s.state.store(kActive);
}

ScratchPath& ScratchPath::operator=(ScratchPath&& other) noexcept {
  if (this != &other) {
    if (slot_ >= 0) g_scratch[slot_].state.store(kFree);
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

ScratchPath::~ScratchPath() {
  if (slot_ >= 0) g_scratch[slot_].state.store(kFree);
}

ChildProcess::ChildProcess(pid_t pid) {
  slot_ = claim(g_children);
  if (slot_ < 0) return;
  g_children[slot_].pid = pid;
  g_children[slot_].state.store(kActive);
}

ChildProcess::~ChildProcess() {
  if (slot_ >= 0) g_children[slot_].state.store(kFree);
}

DeferSignals::DeferSignals() {
  install_handlers();
  g_deferring.fetch_add(1);
}

DeferSignals::~DeferSignals() {
  if (g_deferring.fetch_sub(1) == 1 && g_pending.load() != 0) act(g_pending.load());
}

ForkGuard::ForkGuard() : parent_(::getpid()) {
  const sigset_t block = ending_signals();
  ::pthread_sigmask(SIG_BLOCK, &block, &old_mask_);
}

ForkGuard::~ForkGuard() { ::pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr); }

void ForkGuard::in_child() const {
  for (int sig : kEndingSignals) {
    struct sigaction cur {};
    if (::sigaction(sig, nullptr, &cur) == 0 && cur.sa_handler != SIG_IGN) ::signal(sig, SIG_DFL);
  }
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent_) ::raise(SIGTERM);  // the parent died before the line above: held until unblocked
  ::pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
}

}  // namespace db::cleanup
