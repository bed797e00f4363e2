#pragma once
//! Outputs are written to a temporary next to their target and renamed into place, so a failure never leaves a
//! partial file; StagedOutputs extends that to all the outputs of one run.
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "solvers/base/cleanup.h"

namespace db {

//! Whether two paths name the same file however spelled ("./a.mtx", "DIR/a.mtx", a symbolic or hard link to
//! it); for paths not there yet, whether they resolve to the same place.
bool same_file(const std::string& a, const std::string& b);

//! Calls write(stream) on a temporary file next to path, then renames it to path (a StagedOutputs temporary is
//! written as it is: commit() renames it).
//! \throw Error naming the target once and the cause ("cannot write out.ply: No space left on device") when the
//! file cannot be opened, written or renamed (the temporary is removed).
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                      bool binary = false);

//! All or nothing for the outputs of one run: each is written to a temporary next to its target (the same
//! extension, so writers that go by it still work) and commit() renames them all into place at the end. When a
//! rename fails, the targets already renamed are put back as they were before the run (the earlier file, or none);
//! the destructor removes temporaries never committed (a run that failed halfway leaves no output), and so does a
//! signal that ends the process (cleanup.h), which waits for a commit under way to finish.
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();

  //! The temporary to write instead of `target` ("DIR/NAME.tmp.PID.EXT"). \throw Error when `target` is the
  //! same file as one staged before (two outputs of a run cannot share a file: the second would replace the first
  //! and its earlier version could not be put back).
  std::string stage(const std::string& target);
  //! Renames every staged temporary to its target. \throw Error naming the target that failed (every target is
  //! then as it was before: the earlier file, or none).
  void commit();

 private:
  struct Entry {
    std::string target, temporary;
    cleanup::ScratchPath on_signal;  // the temporary, removed on an ending signal (cleanup.h)
  };
  void roll_back(std::size_t committed, const std::vector<std::string>& kept);
  std::vector<Entry> entries_;
};

}  // namespace db
