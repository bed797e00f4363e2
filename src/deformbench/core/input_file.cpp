#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

InputFile::InputFile(const std::string& path, const std::string& what, std::uint64_t max_bytes)
    : path_(path), what_(what) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw InputError(fmt::format("cannot open {} file: {} ({})", what, path, std::strerror(errno)));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    const bool dir = S_ISDIR(st.st_mode);
    ::close(fd_);
    throw InputError(fmt::format("cannot open {} file: {} ({})", what, path,
                                 dir ? "is a directory" : "not a regular file: a pipe or a device is not read"));
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  if (size_ > max_bytes) {
    ::close(fd_);
    throw InputError(fmt::format("{} file {} holds {} bytes, more than such a file can sensibly hold ({} bytes)",
                                 what, path, size_, max_bytes));
  }
  // Regular files never block; reads go back to ordinary blocking semantics.
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t InputFile::read(char* buf, std::size_t n) {
  for (;;) {
    const ssize_t got = ::read(fd_, buf, n);
    if (got >= 0) return static_cast<std::size_t>(got);
    if (errno != EINTR)
      throw InputError(fmt::format("cannot read {} file: {} ({})", what_, path_, std::strerror(errno)));
  }
}

std::string InputFile::read_all() {
  std::string data(static_cast<std::size_t>(size_), '\0');
  std::size_t done = 0;
  while (done < data.size()) {
    const std::size_t got = read(data.data() + done, data.size() - done);
    if (got == 0) break;  // shrank while read
    done += got;
  }
  data.resize(done);
  return data;
}

void InputFile::each_line(std::size_t max_line, const std::function<void(int, const std::string&)>& fn) {
  std::string line;
  char buf[1 << 16];
  int n = 0;
  for (std::size_t got; (got = read(buf, sizeof buf)) > 0;) {
    for (std::size_t i = 0; i < got;) {
      const char* nl = static_cast<const char*>(std::memchr(buf + i, '\n', got - i));
      const std::size_t end = nl ? static_cast<std::size_t>(nl - buf) : got;
      if (line.size() + (end - i) > max_line)
        throw InputError(fmt::format("{}: line {}: longer than {} bytes (not a {} file?)", path_, n + 1, max_line,
                                     what_));
      if (std::memchr(buf + i, '\0', end - i))
        throw InputError(fmt::format("{}: line {}: holds a NUL byte (a binary file, not a {} file?)", path_,
                                     n + 1, what_));
      line.append(buf + i, end - i);
      if (!nl) break;
      fn(++n, line);
      line.clear();
      i = end + 1;
    }
  }
  if (!line.empty()) fn(++n, line);
}

std::uint64_t input_bytes(const std::vector<std::string>& paths) {
  std::uint64_t sum = 0;
  for (const std::string& p : paths) {
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode)) sum += static_cast<std::uint64_t>(st.st_size);
  }
  return sum;
}

}  // namespace db
