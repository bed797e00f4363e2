#pragma once
//! What an interrupted run leaves behind: nothing. The signals that end a process by default and stop runs in
//! practice (SIGINT and SIGTERM; SIGHUP, SIGQUIT, SIGPIPE, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU: "ending signals"
//! below) run one async-signal-safe handler that ends the registered child processes, removes the registered
//! scratch (staged outputs, out-of-core files, the children's outputs) and then ends the process by the same
//! signal (default action), so its exit status is the shell's 128 + signal: 130 for SIGINT, 143 for SIGTERM
//! (docs/cli.md, exit codes). SIGXFSZ is ignored, so a file-size limit fails the write instead. The handlers are
//! installed by the first registration; a process that never registers anything keeps the default actions.
//!
//! The registry is fixed-size static storage (the handler allocates nothing): a registration that finds no free
//! slot is not cleaned on a signal (the normal paths still remove it).
#include <signal.h>
#include <sys/types.h>

#include <string>

namespace db::cleanup {

//! Registers a scratch file (`path`) or the files of a directory whose names begin with a prefix
//! (`path` = "DIR/PREFIX", matching = Prefix) for removal on an ending signal, for the life of this object.
//! Removing the file itself stays the owner's job on the normal paths.
class ScratchPath {
 public:
  enum Matching { Exact, Prefix };
  ScratchPath() = default;  //!< nothing registered
  explicit ScratchPath(const std::string& path, Matching matching = Exact);
  ScratchPath(ScratchPath&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  ScratchPath& operator=(ScratchPath&& other) noexcept;
  ScratchPath(const ScratchPath&) = delete;
  ScratchPath& operator=(const ScratchPath&) = delete;
  ~ScratchPath();

 private:
  int slot_ = -1;
};

//! Registers a running child process: on an ending signal it gets SIGINT (for a SIGINT) or SIGTERM and is waited
//! for (SIGKILL after a grace period), so an interrupted parent never leaves it running.
class ChildProcess {
 public:
  explicit ChildProcess(pid_t pid);
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();

 private:
  int slot_ = -1;
};

//! While one lives (in any thread), an ending signal is held back and acted on when the last one ends: the
//! renames that commit a run's outputs finish together, or the run ends before the first of them.
class DeferSignals {
 public:
  DeferSignals();
  DeferSignals(const DeferSignals&) = delete;
  DeferSignals& operator=(const DeferSignals&) = delete;
  ~DeferSignals();
};

//! Around a fork: the ending signals deferred (DeferSignals) and blocked in this thread, so the child starts with them
//! blocked and none is lost between the fork and its exec; the parent registers the child (ChildProcess) before
//! this ends. The child calls in_child() before it execs.
class ForkGuard {
 public:
  ForkGuard();
  ForkGuard(const ForkGuard&) = delete;
  ForkGuard& operator=(const ForkGuard&) = delete;
  ~ForkGuard();
  //! In the forked child, before exec (async-signal-safe): the default action for the ending signals (unless they
  //! were ignored) and the signal mask of before the guard, so a signal already sent ends the child; and SIGTERM
  //! when the forking thread ends (PR_SET_PDEATHSIG, kept across exec), so a parent that dies however it dies
  //! (even by a signal handled on another thread while it forked) leaves no child running.
  void in_child() const;

 private:
  DeferSignals defer_;
  sigset_t old_mask_;
  pid_t parent_;
};

//! Installs the ending signals' handlers now (idempotent; registration does it too).
void install_handlers();

}  // namespace db::cleanup
