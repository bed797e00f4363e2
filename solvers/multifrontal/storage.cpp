#include "solvers/multifrontal/storage.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db::multifrontal {

std::uintptr_t page_size() {
  static const std::uintptr_t p = std::uintptr_t(::sysconf(_SC_PAGESIZE));
  return p;
}

Mapping::Mapping(std::size_t count, const char* what) : bytes_(std::max<std::size_t>(count, 1) * sizeof(double)) {
  void* p = ::mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw BudgetError(fmt::format("multifrontal: cannot map {} MB for {}", bytes_ >> 20, what));
#ifdef MADV_HUGEPAGE
  if (bytes_ >= (std::size_t(2) << 20)) ::madvise(p, bytes_, MADV_HUGEPAGE);
#endif
  data_ = static_cast<double*>(p);
}

namespace {

//! An unlinked scratch file in `dir`, or -1 (errno says why).
int scratch_file(const std::string& dir) {
  int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0) {  // a file system without O_TMPFILE: a named file, unlinked at once
    std::string name = dir + "/deformbench-factor-XXXXXX";
    fd = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd >= 0) ::unlink(name.c_str());
  }
  return fd;
}

}  // namespace

Mapping Mapping::on_file(std::size_t count, const char* what, const std::string& dir) {
  Mapping m;
  m.bytes_ = std::max<std::size_t>(count, 1) * sizeof(double);
  const int fd = scratch_file(dir);
  if (fd < 0)
    throw Error(fmt::format("multifrontal: cannot create a scratch file for {} in '{}': {}", what, dir,
                            std::strerror(errno)));
  if (const int err = ::posix_fallocate(fd, 0, off_t(m.bytes_)); err != 0) {
    ::close(fd);
    throw BudgetError(fmt::format("multifrontal: cannot reserve {} MB in '{}' for {}: {}", m.bytes_ >> 20, dir, what,
                                  std::strerror(err)));
  }
  void* p = ::mmap(nullptr, m.bytes_, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int map_errno = errno;
  if (p == MAP_FAILED) ::close(fd);
  if (p == MAP_FAILED)
    throw BudgetError(fmt::format("multifrontal: cannot map {} MB of '{}' for {}: {}", m.bytes_ >> 20, dir, what,
                                  std::strerror(map_errno)));
  m.data_ = static_cast<double*>(p);
  m.on_file_ = true;
  m.fd_ = fd;
  return m;
}

Mapping::~Mapping() {
  if (data_) ::munmap(data_, bytes_);
  if (fd_ >= 0) ::close(fd_);
}

void Mapping::read(const double* from, std::size_t count, double* out) const {
  auto* dst = reinterpret_cast<char*>(out);
  std::size_t left = count * sizeof(double);
  off_t at = off_t(reinterpret_cast<const char*>(from) - reinterpret_cast<const char*>(data_));
  while (left > 0) {
    const ssize_t got = ::pread(fd_, dst, left, at);
    if (got <= 0) {
      if (got < 0 && errno == EINTR) continue;
      throw Error(fmt::format("multifrontal: reading the factor back from its scratch file failed: {}",
                              got < 0 ? std::strerror(errno) : "unexpected end of file"));
    }
    dst += got;
    at += got;
    left -= std::size_t(got);
  }
}

UpdatePool::UpdatePool(std::size_t count) : units_((count + kUnit - 1) / kUnit) {
  if (units_ == 0) return;
  memory_ = Mapping(units_ * kUnit, "the update matrices");
  free_.emplace(0, units_);
}

double* UpdatePool::take(std::size_t count) {
  const std::size_t want = std::max<std::size_t>(1, (count + kUnit - 1) / kUnit);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (closed_) return nullptr;
  // First fit: the lowest addresses are reused first, so the pages touched stay near the peak in use.
  for (auto it = free_.begin(); it != free_.end(); ++it)
    if (it->second >= want) {
      const std::size_t at = it->first, left = it->second - want;
      free_.erase(it);
      if (left > 0) free_.emplace(at + want, left);
      return memory_.get() + at * kUnit;
    }
  return nullptr;
}

void UpdatePool::give(double* p, std::size_t count) {
  std::size_t at = std::size_t(p - memory_.get()) / kUnit, len = std::max<std::size_t>(1, (count + kUnit - 1) / kUnit);
  const std::lock_guard<std::mutex> lock(mutex_);
  auto next = free_.lower_bound(at);
  if (next != free_.begin()) {  // merge with the free range before
    auto prev = std::prev(next);
    if (prev->first + prev->second == at) {
      at = prev->first;
      len += prev->second;
      free_.erase(prev);
    }
  }
  if (next != free_.end() && at + len == next->first) {  // and the one after
    len += next->second;
    free_.erase(next);
  }
  free_.emplace(at, len);
  if (closed_) release(at, len);
}

void UpdatePool::close() {
  const std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  for (const auto& [at, len] : free_) release(at, len);
}

void UpdatePool::release(std::size_t at, std::size_t len) const {
  const std::uintptr_t a = page_up(reinterpret_cast<std::uintptr_t>(memory_.get() + at * kUnit)),
                       e = page_down(reinterpret_cast<std::uintptr_t>(memory_.get() + (at + len) * kUnit));
  if (e > a) ::madvise(reinterpret_cast<void*>(a), e - a, MADV_DONTNEED);
}

UpdateBlock::UpdateBlock(int r, bool zeroed, UpdatePool* pool) : r_(r) {
  const std::size_t total = entries(r);
  if (mapped(r)) {
    mapped_ = Mapping(total, "an update matrix");  // zero-filled by the kernel
    data_ = mapped_.get();
    return;
  }
  if (pool && (data_ = pool->take(total)) != nullptr) {
    pool_ = pool;
  } else {
    heap_.reset(new double[std::max<std::size_t>(total, 1)]);
    data_ = heap_.get();
  }
  if (zeroed) std::fill(data_, data_ + total, 0.0);
}

ColumnRelease::ColumnRelease(const SpMat& A, bool enabled)
    : A_(A), on_(enabled && std::size_t(A.nonZeros()) * sizeof(double) >= (std::size_t(16) << 20)) {}

void ColumnRelease::start(int col) {
  if (!on_) return;
  for (int a = 0; a < 2; ++a) done_[a] = page_up(at(a, col));
}

void ColumnRelease::dead_before(int col, bool all) {
  if (!on_) return;
  for (int a = 0; a < 2; ++a) {
    const std::uintptr_t end = page_down(at(a, col));
    if (end > done_[a] && (all || end - done_[a] >= (std::uintptr_t(1) << 20))) {
      ::madvise(reinterpret_cast<void*>(done_[a]), end - done_[a], MADV_DONTNEED);
      done_[a] = end;
    }
  }
}

std::uintptr_t ColumnRelease::at(int a, int col) const {
  const std::size_t k = std::size_t(A_.outerIndexPtr()[col]);
  return a == 0 ? reinterpret_cast<std::uintptr_t>(A_.valuePtr() + k)
                : reinterpret_cast<std::uintptr_t>(A_.innerIndexPtr() + k);
}

}  // namespace db::multifrontal
