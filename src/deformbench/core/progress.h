#pragma once
//! Progress of a long loop on stderr: "LABEL D/N (P%), E s elapsed, about R s left", printed at most once per
//! interval and never before the first interval has passed, so a short run prints nothing. The interval is
//! DEFORMBENCH_PROGRESS_SECONDS when set (0: after every step, for tests), else 1 s on a terminal (one line
//! rewritten in place) and 10 s otherwise (one line each, for logs). Nothing goes to stdout.
#include <string>

#include "core/timer.h"

namespace db {

class Progress {
 public:
  //! \param enabled false: every call is a no-op (the caller decides, e.g. --progress or stderr a terminal).
  Progress(std::string label, long long total, bool enabled);
  //! Step `done` of `total` has finished.
  void operator()(long long done);
  //! Ends the in-place line on a terminal (a no-op when nothing was printed).
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

 private:
  std::string label_;
  long long total_;
  bool enabled_, tty_, printed_ = false;
  double interval_, next_;
  Timer clock_;
};

//! True when stderr is a terminal (progress is on by default there).
bool stderr_is_terminal();

}  // namespace db
