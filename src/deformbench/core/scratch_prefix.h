#pragma once
//! A command's scratch files, named by one prefix in the temporary directory (TMPDIR/deformbench-NAME-PID-...):
//! every file with the prefix is removed when the object ends (normal paths and exceptions) and by the SIGINT /
//! SIGTERM handler (solvers/base/cleanup.h), so neither a failure nor an interrupt leaves scratch behind. Files,
//! not a directory: the signal handler removes files by prefix and allocates nothing.
#include <string>

#include "solvers/base/cleanup.h"

namespace db {

class ScratchPrefix {
 public:
  //! Files named TMPDIR/deformbench-`name`-PID-...
  explicit ScratchPrefix(const std::string& name);
  ~ScratchPrefix();
  ScratchPrefix(const ScratchPrefix&) = delete;
  ScratchPrefix& operator=(const ScratchPrefix&) = delete;
  //! The path of scratch file `leaf` (the prefix + `leaf`).
  std::string path(const std::string& leaf) const { return prefix_ + leaf; }

 private:
  std::string prefix_;
  cleanup::ScratchPath on_signal_;
};

}  // namespace db
