#pragma once
//! Running a command in a fresh child process (fork + exec, no shell) under a wall-clock limit, with its output,
//! exit status, times and peak memory: the experiment harness's cells and `deformbench advise`'s backends.
#include <cstddef>
#include <string>
#include <vector>

namespace db {

struct ChildRun {
  int exit_code = -1;       //!< exit status when the child exited normally, else -1
  int term_signal = 0;      //!< signal that ended the child, 0 when it exited
  bool timed_out = false;   //!< killed by us after the wall-clock limit
  std::string out, err;     //!< everything the child wrote to stdout / stderr
  double wall_s = 0, user_s = 0, sys_s = 0;
  //! wait4()'s ru_maxrss in bytes. Linux folds the high-water mark of the pre-exec image (the forked copy of
  //! the parent, i.e. the parent's resident anonymous memory at fork time) into it, so it is an upper bound;
  //! the child's own VmHWM (read by the child itself) is the clean figure.
  std::size_t ru_maxrss_bytes = 0;

  bool ok() const { return exit_code == 0 && term_signal == 0 && !timed_out; }
  //! "exit 3", "signal 9 (Killed)", "timed out after 12.0 s".
  std::string describe() const;
  //! The last `max_chars` characters of stderr on one line (newlines as spaces), for error messages.
  std::string stderr_tail(std::size_t max_chars) const;
};

//! Forks, execs argv[0] with argv (no shell, no PATH search), collects stdout and stderr through pipes and waits
//! with wait4(). timeout_s > 0: SIGKILL after that many wall-clock seconds. Never throws for a failing child
//! (that is reported in the result); throws Error only when fork / pipe fail or argv is empty.
ChildRun run_child(const std::vector<std::string>& argv, double timeout_s = 0);

//! Absolute path of the running executable (/proc/self/exe), for re-executing the driver in cell mode.
std::string self_executable();

//! Caps this process's address space (bytes; 0: no cap), so an underpredicted cell fails with bad_alloc
//! instead of being OOM-killed. No cap in an AddressSanitizer build (its shadow memory needs the address space).
void limit_address_space(std::size_t bytes);

}  // namespace db
