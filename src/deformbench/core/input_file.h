#pragma once
//! The one way input files are opened for reading (meshes, edits, selections, transforms, targets, index lists,
//! positions, CSVs): without blocking, regular files only, their size checked before a byte is read.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace db {

//! No bound on an input's size beyond what its reader derives.
constexpr std::uint64_t kAnySize = UINT64_MAX;

//! An open input file. The open never blocks (O_NONBLOCK; a FIFO without a writer, a device or a directory is
//! refused by fstat before any read, so a pipe cannot hang a run and /dev/zero cannot be read without end).
class InputFile {
 public:
  //! Opens `path` (`what` names it in messages: "mesh", "targets", ...) and checks it holds at most max_bytes.
  //! \throw InputError naming what, the path and the cause (strerror, "not a regular file", the size and bound).
  InputFile(const std::string& path, const std::string& what, std::uint64_t max_bytes = kAnySize);
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile();

  std::uint64_t size() const { return size_; }
  //! Up to n bytes into buf; 0 at the end. \throw InputError when the read fails.
  std::size_t read(char* buf, std::size_t n);
  //! The rest of the file.
  std::string read_all();
  //! Calls fn(line number, line) for each line (without '\n'), streaming; a line longer than max_line bytes is an
  //! error at that line, so a file without line ends (a sparse file of zeros) is refused after max_line bytes.
  //! A NUL byte is an error at its line: a text file holds none, and a message quoting the line would end there.
  void each_line(std::size_t max_line, const std::function<void(int, const std::string&)>& fn);

 private:
  std::string path_, what_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

//! Size of each existing regular file in `paths`, summed (for checking inputs against a memory budget before they
//! are read; missing ones count 0 and are reported by their reader).
std::uint64_t input_bytes(const std::vector<std::string>& paths);

}  // namespace db
