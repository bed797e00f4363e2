#pragma once
//! Memory of the multifrontal backend: the layout of a supernode's factor (FactorBlock) and of its update matrix
//! (UpdateBlock), both without the part above the diagonal; the mappings that hold them (anonymous, or a scratch
//! file when the factor is kept out of core); and the release of a consumed input matrix's pages.
//! Why mappings and not the heap: freed heap blocks stay in the process (glibc keeps them for reuse), so the
//! large update matrices near the root, freed during the factorization, stayed resident next to the whole factor;
//! a mapping goes back to the OS when released.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include <sys/mman.h>

#include "solvers/base/types.h"

namespace db::multifrontal {

//! Offset of column j of a packed lower triangle of order w (columns of lengths w, w - 1, ...).
inline std::size_t packed_column(int j, int w) {
  return std::size_t(j) * std::size_t(w) - std::size_t(j) * std::size_t(j - 1) / 2;
}

//! A supernode's factor: the lower trapezoid of its m rows x n columns (n <= m, the diagonal block on top) in
//! column panels of kWidth columns. Panel p (columns c0 = p kWidth .. c0 + w) stores its w x w diagonal block
//! as a packed lower triangle, then the h = m - c0 - w rows below it as a column-major h x w rectangle, the
//! operand dtrsm and dgemm take. Exactly the trapezoid's m n - n (n - 1) / 2 entries. T: the entries' type
//! (double; const float for the mixed backend's rounded factor, the same layout).
template <class T>
struct FactorBlockOf {
  static constexpr int kWidth = 256;  // the k of the panel updates' dgemm calls; the dpotrf scratch is kWidth^2
  T* base;
  int m, n;

  static std::size_t size(int m, int n) {
    return std::size_t(m) * std::size_t(n) - std::size_t(n) * std::size_t(n - 1) / 2;
  }
  int panels() const { return (n + kWidth - 1) / kWidth; }
  int c0(int p) const { return p * kWidth; }
  int width(int p) const { return std::min(kWidth, n - p * kWidth); }
  int height(int p) const { return m - c0(p) - width(p); }  //!< rows of panel p's rectangle
  T* tri(int p) const {
    // Every panel before p is kWidth wide.
    const std::size_t K = kWidth, q = std::size_t(p);
    return base + q * K * (K + 1) / 2 + K * (q * std::size_t(m) - K * q * (q + 1) / 2);
  }
  T* rect(int p) const { return tri(p) + std::size_t(width(p)) * std::size_t(width(p) + 1) / 2; }
};
using FactorBlock = FactorBlockOf<double>;

std::uintptr_t page_size();
inline std::uintptr_t page_up(std::uintptr_t x) { return (x + page_size() - 1) & ~(page_size() - 1); }
inline std::uintptr_t page_down(std::uintptr_t x) { return x & ~(page_size() - 1); }

//! Doubles in a mapping of their own, zero-filled.
//!  - Anonymous (the default): advised for transparent huge pages where the kernel offers them ("madvise"
//!    mode): first-touch faults on 4 KB pages of a factor are a visible part of the factorization, and the
//!    solves stream through the factor every frame.
//!  - On a file (out of core): an unlinked scratch file, its blocks reserved up front so that a full disk is a
//!    clear error here and not a SIGBUS on some later write. Its pages belong to the page cache: release() drops
//!    them from this process's resident set and the kernel writes them back and may evict them; read() copies a
//!    range back (pread) without mapping it again.
class Mapping {
 public:
  Mapping() = default;
  //! `count` anonymous doubles; `what` names them in errors. \throw BudgetError when they cannot be mapped.
  Mapping(std::size_t count, const char* what);
  //! `count` doubles in a scratch file in directory `dir`. \throw Error when it cannot be created (no such
  //! directory), BudgetError when its space cannot be reserved (disk full).
  static Mapping on_file(std::size_t count, const char* what, const std::string& dir);
  Mapping(Mapping&& o) noexcept : data_(o.data_), bytes_(o.bytes_), on_file_(o.on_file_), fd_(o.fd_) {
    o.data_ = nullptr;
    o.fd_ = -1;
  }
  Mapping& operator=(Mapping&& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(bytes_, o.bytes_);
    std::swap(on_file_, o.on_file_);
    std::swap(fd_, o.fd_);
    return *this;
  }
  Mapping(const Mapping&) = delete;
  Mapping& operator=(const Mapping&) = delete;
  ~Mapping();
  double* get() const { return data_; }
  explicit operator bool() const { return data_ != nullptr; }
  void reset() { *this = Mapping(); }
  //! On a file: drops the pages holding [from, to) from the resident set, whole pages outward. The data stays:
  //! a shared file page written by another thread meanwhile keeps that write (dropping only unmaps it).
  void release(const double* from, const double* to) const {
    if (!on_file_ || from >= to) return;
    const std::uintptr_t a = page_down(reinterpret_cast<std::uintptr_t>(from)),
                         e = page_up(reinterpret_cast<std::uintptr_t>(to));
    ::madvise(reinterpret_cast<void*>(a), e - a, MADV_DONTNEED);
  }
  bool on_file() const { return on_file_; }
  //! On a file: copies the `count` doubles at `from` (inside this mapping) to `out` with pread(), from the page
  //! cache or the disk, without mapping them into this process. Why: pages released from the mapping cost a
  //! page fault each to map again, and on a virtual machine that is dear (pread was several times faster; the
  //! measurement is in commit 90b63c7). \throw Error when the read fails.
  void read(const double* from, std::size_t count, double* out) const;

 private:
  double* data_ = nullptr;
  std::size_t bytes_ = 0;
  bool on_file_ = false;
  int fd_ = -1;  //!< the scratch file, kept open for read()
};

//! Recycled memory for the update matrices of one factorization: one mapping, advised for huge pages, handed out
//! first-fit in 64-byte units and taken back when a matrix dies; thread-safe. Why: some 2 GB of update matrices
//! pass through the 104k TF factorization with under 100 MB of them alive at once. From the heap each one's
//! pages were faulted in anew, 4 KB at a time (glibc maps large blocks and hands them back when freed), and on
//! a virtual machine a fault costs microseconds: half the page faults of the whole run. Here the pages are
//! faulted once, 2 MB at a time, and reused.
class UpdatePool {
 public:
  //! Room for `count` doubles (reserved, not touched); 0: no pool (take() always fails).
  explicit UpdatePool(std::size_t count);
  //! `count` doubles, not zeroed; null when no free range is large enough (the caller allocates elsewhere).
  double* take(std::size_t count);
  //! Returns a block that take() handed out, with the same count.
  void give(double* p, std::size_t count);
  //! No further take(); the pages of the free ranges go back to the OS (whole pages; live blocks stay).
  void close();

 private:
  static constexpr std::size_t kUnit = 8;  // doubles: 64 bytes
  void release(std::size_t at, std::size_t len) const;  //!< the whole pages of a free range, to the OS
  std::mutex mutex_;
  Mapping memory_;
  std::size_t units_ = 0;
  std::map<std::size_t, std::size_t> free_;  //!< free ranges: first unit -> units
  bool closed_ = false;
};

//! A supernode's update matrix (its r x r Schur complement, lower triangle) in column panels of kWidth
//! columns: panel u (columns u0 = u kWidth .. u0 + w) is a column-major (r - u0) x w block from row u0 down.
//! Half the memory of the full square the extend-add needs, and dsyrk/dgemm write it directly.
class UpdateBlock {
 public:
  static constexpr int kWidth = 128;
  UpdateBlock() = default;
  //! `zeroed`: whether the entries must start at zero (a heap or pooled block is otherwise left uninitialized,
  //! for a first product with beta = 0 to write). Blocks below the own-mapping size come from `pool` when it
  //! has room, else from the heap.
  UpdateBlock(int r, bool zeroed, UpdatePool* pool = nullptr);
  UpdateBlock(UpdateBlock&& o) noexcept { *this = std::move(o); }
  UpdateBlock& operator=(UpdateBlock&& o) noexcept {
    std::swap(r_, o.r_);
    std::swap(data_, o.data_);
    std::swap(mapped_, o.mapped_);
    std::swap(heap_, o.heap_);
    std::swap(pool_, o.pool_);
    return *this;
  }
  ~UpdateBlock() {
    if (pool_) pool_->give(data_, entries(r_));
  }
  int panels() const { return (r_ + kWidth - 1) / kWidth; }
  int width(int u) const { return std::min(kWidth, r_ - u * kWidth); }
  //! Whether an update matrix of order r gets a mapping of its own (and is zero-filled by the kernel).
  static bool mapped(int r) { return bytes(r) >= kMapBytes; }
  static std::size_t bytes(int r) { return entries(r) * sizeof(double); }
  //! Panel u; its leading dimension is r - u kWidth.
  double* panel(int u) const {
    // Panels before u are kWidth wide and r, r - kWidth, ... tall.
    const std::size_t K = kWidth, q = std::size_t(u);
    return data_ + K * q * std::size_t(r_) - K * K * (q * q - q) / 2;
  }
  //! Column j from its diagonal entry down: entry (i, j), i >= j, is col(j)[i - j].
  const double* col(int j) const {
    const int u = j / kWidth, u0 = u * kWidth;
    return panel(u) + std::size_t(j - u0) * std::size_t(r_ - u0) + std::size_t(j - u0);
  }
  double* col(int j) { return const_cast<double*>(static_cast<const UpdateBlock*>(this)->col(j)); }
  explicit operator bool() const { return data_ != nullptr; }

 private:
  // Smaller blocks come from the heap: mapping them too kept a little less resident, but their page faults
  // cost a noticeable part of the factorization.
  static constexpr std::size_t kMapBytes = std::size_t(16) << 20;
  static std::size_t entries(int r) {  // panels of kWidth columns, r, r - kWidth, ... rows
    const std::size_t q = std::size_t(r / kWidth), K = kWidth, R = std::size_t(r);
    return K * (q * R - K * q * (q - 1) / 2) + (R - q * K) * (R - q * K);
  }
  int r_ = 0;
  double* data_ = nullptr;
  Mapping mapped_;
  std::unique_ptr<double[]> heap_;
  UpdatePool* pool_ = nullptr;  //!< where data_ came from, when from a pool
};

//! Hands A's pages back to the OS as its columns die, in one thread's run of consecutive supernodes. Column i
//! is read only by its own supernode and that supernode's descendants, all numbered below it, so after
//! supernode s every column of the run up to s's last one is dead. Whole pages only (a page at either end of
//! the run may hold another run's live columns), in steps of at least a megabyte; dead pages read as zero.
class ColumnRelease {
 public:
  //! Does nothing unless `enabled` and A's values are large enough to matter.
  ColumnRelease(const SpMat& A, bool enabled);
  //! A run starts at column `col`.
  void start(int col);
  //! Columns before `col` are dead; `all`: release what is whole-page dead now, however little.
  void dead_before(int col, bool all = false);

 private:
  std::uintptr_t at(int a, int col) const;  // a = 0: values, 1: row indices
  const SpMat& A_;
  bool on_;
  std::uintptr_t done_[2] = {0, 0};
};

}  // namespace db::multifrontal
