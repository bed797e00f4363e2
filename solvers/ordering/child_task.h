#pragma once
//! A computation in a forked child process, for the METIS orderings (graph_ordering, ring_dissection).
#include <cerrno>
#include <cstddef>
#include <optional>
#include <vector>

#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

namespace db {

//! A vector of `count` ints computed by a forked child process while this one goes on, sent back through a
//! pipe. Why a process and not a thread: METIS draws its random numbers from the C library's one shared
//! generator, reseeded at every call, so two orderings on two threads would interleave their draws and come out
//! different from run to run.
class ChildTask {
 public:
  template <class Fn>
  ChildTask(std::size_t count, Fn fn) : count_(count) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    // Free heap pages are handed back first: after the fork both processes share every resident page
    // copy-on-write, and the allocator reuses free heap for their METIS work arrays, so each write there would
    // copy a page (and, with other threads alive, flush the TLBs of every core); a page handed back is mapped
    // afresh, zero-filled, without a copy.
    ::malloc_trim(0);
    pid_ = ::fork();
    if (pid_ < 0) {
      ::close(fds[0]);
      ::close(fds[1]);
      return;
    }
    if (pid_ == 0) {  // the child: compute, write, leave without running the parent's exit handlers
      ::close(fds[0]);
      bool ok = false;
      try {
        std::vector<int> out = fn();
        ok = out.size() == count && transfer(fds[1], out.data(), count, true);
      } catch (...) {
      }
      ::_exit(ok ? 0 : 1);
    }
    ::close(fds[1]);
    fd_ = fds[0];
  }
  ChildTask(const ChildTask&) = delete;
  ChildTask& operator=(const ChildTask&) = delete;
  ~ChildTask() { result(); }

  //! The child's answer; empty when it could not be started or did not deliver (the caller then computes it).
  std::optional<std::vector<int>> result() {
    if (pid_ <= 0) return std::nullopt;
    std::vector<int> out(count_);
    const bool got = transfer(fd_, out.data(), count_, false);
    ::close(fd_);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
    return out;
  }

 private:
  static bool transfer(int fd, int* data, std::size_t count, bool write) {
    char* p = reinterpret_cast<char*>(data);
    std::size_t left = count * sizeof(int);
    while (left > 0) {
      const ssize_t k = write ? ::write(fd, p, left) : ::read(fd, p, left);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) return false;
      p += k;
      left -= static_cast<std::size_t>(k);
    }
    return true;
  }

  std::size_t count_;
  pid_t pid_ = -1;
  int fd_ = -1;
};

}  // namespace db
