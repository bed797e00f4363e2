//! "multifrontal": supernodal multifrontal Cholesky LL^T for systems of b x b blocks (TF: b = 3).
//!
//! Why a backend of our own next to CHOLMOD: on the 104k-vertex TF system CHOLMOD's left-looking
//! supernodal factorization ran at ~18 GFlop/s on two cores, a fifth of what the BLAS reaches, and its
//! symbolic analysis ran on the 3n-unknown matrix. Here
//!  - the symbolic analysis (ordering, elimination tree, postorder, relaxed supernodes) is CHOLMOD's, run on
//!    the compressed block (vertex) graph, ~b^2 times smaller, and expanded: with dense b x b blocks the
//!    factor of the expanded matrix is exactly the expanded factor of the block graph;
//!  - the numeric phase is multifrontal: each supernode assembles a dense front from the matrix and its
//!    children's update matrices, then dpotrf, dtrsm and dsyrk/dgemm on column panels (large BLAS-3 calls);
//!  - nothing above the diagonal is stored: a supernode's factor is a lower trapezoid in column panels with
//!    packed diagonal triangles (FactorBlock), its update matrix a lower triangle in column panels
//!    (UpdateBlock); full m x n blocks cost 15% more factor memory on the 104k TF system and twice the
//!    update memory;
//!  - independent subtrees of the assembly tree run on separate threads with a single-threaded BLAS, the
//!    few top fronts after them with the multithreaded BLAS; the solves are split the same way.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cholmod.h>
#include <fmt/format.h>

#include "core/error.h"
#include "core/resources.h"
#include "solvers/backends.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/solver_util.h"

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb, std::size_t,
            std::size_t, std::size_t, std::size_t);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc, std::size_t, std::size_t);
}

namespace db {
namespace {

using namespace solver_util;

//! OpenBLAS runs its own thread pool; while our threads each factor a subtree it must run single-threaded
//! (two pools on two cores oversubscribe). Looked up at run time: other BLAS builds simply lack the symbol.
class BlasThreads {
 public:
  BlasThreads() {
    void* self = ::dlopen(nullptr, RTLD_LAZY);
    set_ = reinterpret_cast<void (*)(int)>(::dlsym(self, "openblas_set_num_threads"));
    get_ = reinterpret_cast<int (*)()>(::dlsym(self, "openblas_get_num_threads"));
  }
  int get() const { return get_ ? get_() : 1; }
  void set(int n) const {
    if (set_) set_(n);
  }

 private:
  void (*set_)(int) = nullptr;
  int (*get_)() = nullptr;
};

const BlasThreads& blas_threads() {
  static const BlasThreads b;
  return b;
}

//! Symbolic factorization at the scalar level. Supernodes are numbered in a postorder of the assembly tree,
//! so the subtree of s is the contiguous range [first[s], s].
struct Symbolic {
  int n = 0;
  std::vector<int> perm;  //!< perm[k] = original index of unknown k; empty when the identity
  std::vector<int> col0;  //!< nsuper + 1: first column of each supernode
  std::vector<int> rptr;  //!< nsuper + 1: offsets into rows
  std::vector<int> rows;  //!< row indices of each supernode, its own columns first, ascending
  std::vector<std::size_t> xptr;  //!< nsuper + 1: offsets of the supernodes' FactorBlocks
  std::vector<int> parent, first;
  std::vector<int> cptr, child;  //!< children lists
  double flops = 0;
  std::size_t nnz = 0;

  int nsuper() const { return int(col0.size()) - 1; }
  int ncols(int s) const { return col0[std::size_t(s) + 1] - col0[std::size_t(s)]; }
  int nrows(int s) const { return rptr[std::size_t(s) + 1] - rptr[std::size_t(s)]; }
};

//! Offset of column j of a packed lower triangle of order w (columns of lengths w, w - 1, ...).
inline std::size_t packed_column(int j, int w) {
  return std::size_t(j) * std::size_t(w) - std::size_t(j) * std::size_t(j - 1) / 2;
}

//! A supernode's factor: the lower trapezoid of its m rows x n columns (n <= m, the diagonal block on top) in
//! column panels of kWidth columns. Panel p (columns c0 = p kWidth .. c0 + w) stores its w x w diagonal block
//! as a packed lower triangle, then the h = m - c0 - w rows below it as a column-major h x w rectangle, the
//! operand dtrsm and dgemm take. Exactly the trapezoid's m n - n (n - 1) / 2 entries.
struct FactorBlock {
  static constexpr int kWidth = 256;  // the k of the panel updates' dgemm calls; the dpotrf scratch is kWidth^2
  double* base;
  int m, n;

  static std::size_t size(int m, int n) {
    return std::size_t(m) * std::size_t(n) - std::size_t(n) * std::size_t(n - 1) / 2;
  }
  int panels() const { return (n + kWidth - 1) / kWidth; }
  int c0(int p) const { return p * kWidth; }
  int width(int p) const { return std::min(kWidth, n - p * kWidth); }
  int height(int p) const { return m - c0(p) - width(p); }  //!< rows of panel p's rectangle
  double* tri(int p) const {
    // Every panel before p is kWidth wide.
    const std::size_t K = kWidth, q = std::size_t(p);
    return base + q * K * (K + 1) / 2 + K * (q * std::size_t(m) - K * q * (q + 1) / 2);
  }
  double* rect(int p) const { return tri(p) + std::size_t(width(p)) * std::size_t(width(p) + 1) / 2; }
};

std::uintptr_t page_size() {
  static const std::uintptr_t p = std::uintptr_t(::sysconf(_SC_PAGESIZE));
  return p;
}
std::uintptr_t page_up(std::uintptr_t x) { return (x + page_size() - 1) & ~(page_size() - 1); }
std::uintptr_t page_down(std::uintptr_t x) { return x & ~(page_size() - 1); }

//! Doubles in a mapping of their own, zero-filled. Why not the heap: freed heap blocks stay in the process
//! (glibc keeps them for reuse), so the large update matrices near the root, freed during the factorization,
//! stayed resident next to the whole factor; a mapping goes back to the OS when released.
//!  - Anonymous (the default): advised for transparent huge pages where the kernel offers them ("madvise"
//!    mode): first-touch faults on ~1 GB of 4 KB pages cost a tenth of a second, and the solves stream through
//!    the factor every frame.
//!  - On a file (out of core): an unlinked scratch file, its blocks reserved up front so that a full disk is a
//!    clear error here and not a SIGBUS on some later write. Its pages belong to the page cache: release() drops
//!    them from this process's resident set and the kernel writes them back and may evict them; they come back
//!    from the file when touched again.
class Mapping {
 public:
  Mapping() = default;
  explicit Mapping(std::size_t count, const char* what) : bytes_(std::max<std::size_t>(count, 1) * sizeof(double)) {
    void* p = ::mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw BudgetError(fmt::format("multifrontal: cannot map {} MB for {}", bytes_ >> 20, what));
#ifdef MADV_HUGEPAGE
    if (bytes_ >= (std::size_t(2) << 20)) ::madvise(p, bytes_, MADV_HUGEPAGE);
#endif
    data_ = static_cast<double*>(p);
  }
  //! `count` doubles in a scratch file in directory `dir`. \throw Error when it cannot be created (no such
  //! directory), BudgetError when its space cannot be reserved (disk full).
  static Mapping on_file(std::size_t count, const char* what, const std::string& dir) {
    Mapping m;
    m.bytes_ = std::max<std::size_t>(count, 1) * sizeof(double);
    int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd < 0) {  // a file system without O_TMPFILE: a named file, unlinked at once
      std::string name = dir + "/deformbench-factor-XXXXXX";
      fd = ::mkostemp(name.data(), O_CLOEXEC);
      if (fd >= 0) ::unlink(name.c_str());
    }
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
    ::close(fd);  // the mapping keeps the file
    if (p == MAP_FAILED)
      throw BudgetError(fmt::format("multifrontal: cannot map {} MB of '{}' for {}: {}", m.bytes_ >> 20, dir, what,
                                    std::strerror(map_errno)));
    m.data_ = static_cast<double*>(p);
    m.on_file_ = true;
    return m;
  }
  Mapping(Mapping&& o) noexcept : data_(o.data_), bytes_(o.bytes_), on_file_(o.on_file_) { o.data_ = nullptr; }
  Mapping& operator=(Mapping&& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(bytes_, o.bytes_);
    std::swap(on_file_, o.on_file_);
    return *this;
  }
  Mapping(const Mapping&) = delete;
  Mapping& operator=(const Mapping&) = delete;
  ~Mapping() {
    if (data_) ::munmap(data_, bytes_);
  }
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

 private:
  double* data_ = nullptr;
  std::size_t bytes_ = 0;
  bool on_file_ = false;
};

//! A supernode's update matrix (its r x r Schur complement, lower triangle) in column panels of kWidth
//! columns: panel u (columns u0 = u kWidth .. u0 + w) is a column-major (r - u0) x w block from row u0 down.
//! Half the memory of the full square the extend-add needs, and dsyrk/dgemm write it directly.
class UpdateBlock {
 public:
  static constexpr int kWidth = 128;
  UpdateBlock() = default;
  //! `zeroed`: whether the entries must start at zero (a heap block is otherwise left uninitialized, for a
  //! first product with beta = 0 to write).
  UpdateBlock(int r, bool zeroed) : r_(r) {
    const std::size_t total = entries(r);
    if (mapped(r)) {
      mapped_ = Mapping(total, "an update matrix");  // zero-filled by the kernel
      data_ = mapped_.get();
    } else {
      heap_.reset(new double[std::max<std::size_t>(total, 1)]);
      data_ = heap_.get();
      if (zeroed) std::fill(data_, data_ + total, 0.0);
    }
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
  // Smaller blocks come from the heap: mapping them too kept ~30 MB less resident but its page faults cost
  // ~10% of the 104k TF factorization.
  static constexpr std::size_t kMapBytes = std::size_t(16) << 20;
  static std::size_t entries(int r) {  // panels of kWidth columns, r, r - kWidth, ... rows
    const std::size_t q = std::size_t(r / kWidth), K = kWidth, R = std::size_t(r);
    return K * (q * R - K * q * (q - 1) / 2) + (R - q * K) * (R - q * K);
  }
  int r_ = 0;
  double* data_ = nullptr;
  Mapping mapped_;
  std::unique_ptr<double[]> heap_;
};

//! How the assembly tree is shared among threads: subtrees per thread (processed in parallel), then the top
//! supernodes (ascending, serial).
struct Plan {
  std::vector<std::vector<int>> subtrees;
  std::vector<int> top;
  std::vector<int> top_columns;  //!< columns of the top supernodes (rows several threads update in a solve)
  std::vector<signed char> owner;  //!< per column: thread that owns it, -1 for top columns
};

//! Flops of the dense work of supernode s (sum over its columns of (column count)^2, as CHOLMOD counts).
double supernode_flops(const Symbolic& S, int s) {
  double f = 0;
  const int m = S.nrows(s);
  for (int k = 0; k < S.ncols(s); ++k) f += double(m - k) * double(m - k);
  return f;
}

//! Splits the assembly tree into `threads` groups of independent subtrees of about equal cost (`cost(s)` of
//! each supernode, summed over a subtree) plus the top supernodes above them: the heaviest subtree is opened
//! (its root moves to the top set) until a greedy assignment of the open subtrees balances within 10%.
template <class Cost>
Plan schedule(const Symbolic& S, int threads, Cost cost) {
  Plan P;
  const int ns = S.nsuper();
  std::vector<double> work(std::size_t(ns), 0.0);
  for (int s = 0; s < ns; ++s) {
    work[std::size_t(s)] += cost(s);
    if (S.parent[std::size_t(s)] >= 0) work[std::size_t(S.parent[std::size_t(s)])] += work[std::size_t(s)];
  }
  std::vector<int> open;
  for (int s = 0; s < ns; ++s)
    if (S.parent[std::size_t(s)] < 0) open.push_back(s);
  std::vector<char> is_top(std::size_t(ns), 0);
  P.subtrees.assign(std::size_t(std::max(threads, 1)), {});
  auto assign = [&](std::vector<std::vector<int>>& bins) {
    std::vector<double> load(bins.size(), 0.0);
    for (auto& b : bins) b.clear();
    std::vector<int> order = open;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return work[std::size_t(a)] > work[std::size_t(b)]; });
    for (int s : order) {
      const std::size_t t = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
      bins[t].push_back(s);
      load[t] += work[std::size_t(s)];
    }
    const double total = std::accumulate(load.begin(), load.end(), 0.0);
    return *std::max_element(load.begin(), load.end()) <= 1.1 * total / double(bins.size()) + 1.0;
  };
  if (threads > 1) {
    for (int iter = 0; iter < 4096 && !assign(P.subtrees); ++iter) {
      auto h = std::max_element(open.begin(), open.end(),
                                [&](int a, int b) { return work[std::size_t(a)] < work[std::size_t(b)]; });
      const int s = *h;
      open.erase(h);
      is_top[std::size_t(s)] = 1;
      for (int p = S.cptr[std::size_t(s)]; p < S.cptr[std::size_t(s) + 1]; ++p) open.push_back(S.child[std::size_t(p)]);
      if (open.empty()) break;
    }
    assign(P.subtrees);
  } else {
    P.subtrees[0] = open;
  }
  for (auto& b : P.subtrees) std::sort(b.begin(), b.end());
  P.top.clear();
  for (int s = 0; s < ns; ++s)
    if (is_top[std::size_t(s)]) P.top.push_back(s);
  P.owner.assign(std::size_t(S.n), -1);
  for (std::size_t t = 0; t < P.subtrees.size(); ++t)
    for (int r : P.subtrees[t])
      for (int s = S.first[std::size_t(r)]; s <= r; ++s)
        for (int j = S.col0[std::size_t(s)]; j < S.col0[std::size_t(s) + 1]; ++j) P.owner[std::size_t(j)] = static_cast<signed char>(t);
  P.top_columns.clear();
  for (int s : P.top)
    for (int j = S.col0[std::size_t(s)]; j < S.col0[std::size_t(s) + 1]; ++j) P.top_columns.push_back(j);
  return P;
}

//! Bytes of update matrices alive at once in a factorization by `plan`, an upper bound: each thread's subtrees in
//! order (a supernode's matrix is born while its children's still live; theirs die after it), the threads'
//! peaks summed as if they coincided, plus the matrices of the top supernodes that receive a subtree root's
//! (born during the subtree phase); or the top phase's own peak, when larger.
double update_peak(const Symbolic& S, const Plan& plan) {
  auto U = [&](int s) { return double(UpdateBlock::bytes(S.nrows(s) - S.ncols(s))); };
  std::vector<char> is_top(std::size_t(S.nsuper()), 0);
  for (int s : plan.top) is_top[std::size_t(s)] = 1;
  double subtrees = 0;
  for (const auto& roots : plan.subtrees) {
    double live = 0, peak = 0;
    for (int root : roots) {
      for (int s = S.first[std::size_t(root)]; s <= root; ++s) {
        live += U(s);
        peak = std::max(peak, live);
        for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q) live -= U(S.child[std::size_t(q)]);
      }
      live -= U(root);  // handed to its top parent
    }
    subtrees += peak;
  }
  double early = 0;  // top matrices begun by subtree roots
  std::vector<char> begun(std::size_t(S.nsuper()), 0);
  for (const auto& roots : plan.subtrees)
    for (int root : roots)
      if (const int p = S.parent[std::size_t(root)]; p >= 0 && !begun[std::size_t(p)]) {
        begun[std::size_t(p)] = 1;
        early += U(p);
      }
  double live = early, top = early;
  for (int s : plan.top) {
    if (!begun[std::size_t(s)]) live += U(s);
    top = std::max(top, live);
    for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q)
      if (const int c = S.child[std::size_t(q)]; is_top[std::size_t(c)]) live -= U(c);  // roots' died at handover
  }
  return std::max(subtrees + early, top);
}

//! The "default" ordering: METIS for block systems, AMD for scalar ones, the structured builds' vertex orderings
//! (systems/vertex_ordering.h): on the 2-ring graphs of TF systems METIS saves a third of the flops for a
//! fraction of a second. CHOLMOD's own rule, applied to the smaller block graph, would keep AMD.
const char* default_ordering(int b) { return b > 1 ? "metis" : "amd"; }

//! CHOLMOD's supernodal symbolic analysis of the block graph (ordering `method`, postordered, relaxed
//! supernodes), expanded to b x b blocks.
Symbolic analyze_blocks(const SpMat& upper, int b, const std::string& method) {
  // Upper triangle of the block graph with the diagonal, the pattern CHOLMOD analyzes; a scalar matrix
  // (b = 1) is its own block graph and is viewed in place.
  const int nb = int(upper.cols()) / b;
  std::vector<int> Up, Ui;
  if (b > 1) {
    Up.assign(std::size_t(nb) + 1, 0);
    Ui.reserve(std::size_t(upper.nonZeros()) / std::size_t(b * b) + std::size_t(nb));
    std::vector<int> mark(std::size_t(nb), -1);
    const int* Ap = upper.outerIndexPtr();
    const int* Ai = upper.innerIndexPtr();
    for (int J = 0; J < nb; ++J) {
      const std::size_t start = Ui.size();
      mark[std::size_t(J)] = J;  // the diagonal block, appended last
      for (int j = J * b; j < (J + 1) * b; ++j)
        for (int p = Ap[j]; p < Ap[j + 1]; ++p)
          if (const int I = Ai[p] / b; I < J && mark[std::size_t(I)] != J) {
            mark[std::size_t(I)] = J;
            Ui.push_back(I);
          }
      std::sort(Ui.begin() + std::ptrdiff_t(start), Ui.end());
      Ui.push_back(J);
      Up[std::size_t(J) + 1] = int(Ui.size());
    }
  }
  const GraphPattern G = b > 1 ? GraphPattern{nb, Up.data(), Ui.data()}
                               : GraphPattern{nb, upper.outerIndexPtr(), upper.innerIndexPtr()};

  cholmod_common cc;
  cholmod_start(&cc);
  std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> finish(&cc, cholmod_finish);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SUPERNODAL;
  // CHOLMOD's amalgamation thresholds count columns; a block column is b scalar columns.
  for (int k = 0; k < 3; ++k) cc.nrelax[k] = std::max<std::size_t>(1, (cc.nrelax[k] + std::size_t(b) - 1) / std::size_t(b));
  // The shared graph analysis: METIS on large graphs runs dissected on two processes (solvers/graph_ordering).
  cholmod_factor* L = analyze_graph(G, method == "default" ? default_ordering(b) : method, cc);
  if (!L->is_super) {
    cholmod_free_factor(&L, &cc);
    throw SolverError(fmt::format("multifrontal: the symbolic analysis of the {0}x{0} block graph is not supernodal", nb));
  }
  Symbolic S;
  S.n = nb * b;
  const int ns = int(L->nsuper);
  const int* Perm = static_cast<const int*>(L->Perm);
  const int* super = static_cast<const int*>(L->super);
  const int* pi = static_cast<const int*>(L->pi);
  const int* srow = static_cast<const int*>(L->s);
  bool identity = true;
  for (int k = 0; k < nb; ++k) identity = identity && Perm[k] == k;
  if (!identity) {
    S.perm.resize(std::size_t(S.n));
    for (int k = 0; k < nb; ++k)
      for (int c = 0; c < b; ++c) S.perm[std::size_t(b * k + c)] = b * Perm[k] + c;
  }
  S.col0.resize(std::size_t(ns) + 1);
  S.rptr.assign(std::size_t(ns) + 1, 0);
  S.xptr.assign(std::size_t(ns) + 1, 0);
  S.rows.reserve(std::size_t(pi[ns]) * std::size_t(b));
  std::vector<int> super_of(static_cast<std::size_t>(nb));
  for (int s = 0; s < ns; ++s) {
    S.col0[std::size_t(s)] = b * super[s];
    for (int J = super[s]; J < super[s + 1]; ++J) super_of[std::size_t(J)] = s;
    const std::size_t start = S.rows.size();
    for (int p = pi[s]; p < pi[s + 1]; ++p)
      for (int c = 0; c < b; ++c) S.rows.push_back(b * srow[p] + c);
    // CHOLMOD lists a supernode's own columns first but leaves the rows below unsorted; the extend-add
    // below relies on ascending rows (it maps a child's lower triangle into the parent's lower triangle).
    std::sort(S.rows.begin() + std::ptrdiff_t(start), S.rows.end());
    S.rptr[std::size_t(s) + 1] = int(S.rows.size());
    const std::size_t m = std::size_t(S.rptr[std::size_t(s) + 1] - S.rptr[std::size_t(s)]);
    const std::size_t nc = std::size_t(b) * std::size_t(super[s + 1] - super[s]);
    S.xptr[std::size_t(s) + 1] = S.xptr[std::size_t(s)] + FactorBlock::size(int(m), int(nc));
    S.nnz += FactorBlock::size(int(m), int(nc));
  }
  S.col0[std::size_t(ns)] = S.n;
  S.parent.assign(std::size_t(ns), -1);
  for (int s = 0; s < ns; ++s) {
    const int nsc = super[s + 1] - super[s];
    if (pi[s + 1] - pi[s] > nsc) S.parent[std::size_t(s)] = super_of[std::size_t(S.rows[std::size_t(S.rptr[std::size_t(s)] + b * nsc)] / b)];
  }
  cholmod_free_factor(&L, &cc);
  // Children lists, subtree ranges.
  S.cptr.assign(std::size_t(ns) + 1, 0);
  for (int s = 0; s < ns; ++s)
    if (S.parent[std::size_t(s)] >= 0) ++S.cptr[std::size_t(S.parent[std::size_t(s)]) + 1];
  for (int s = 0; s < ns; ++s) S.cptr[std::size_t(s) + 1] += S.cptr[std::size_t(s)];
  S.child.resize(std::size_t(S.cptr[std::size_t(ns)]));
  std::vector<int> next(S.cptr.begin(), S.cptr.end() - 1);
  S.first.resize(std::size_t(ns));
  std::iota(S.first.begin(), S.first.end(), 0);
  for (int s = 0; s < ns; ++s) {
    const int p = S.parent[std::size_t(s)];
    if (p < 0) continue;
    if (p <= s) throw SolverError("multifrontal: the supernodal tree is not postordered");
    S.child[std::size_t(next[std::size_t(p)]++)] = s;
    S.first[std::size_t(p)] = std::min(S.first[std::size_t(p)], S.first[std::size_t(s)]);
  }
  for (int s = 0; s < ns; ++s) S.flops += supernode_flops(S, s);
  return S;
}

// Dense kernels of the solves on one panel of a FactorBlock: T its packed w x w diagonal triangle, Rr its
// h x w rectangle below, x a column-major block of r right-hand sides (leading dimension ldx) from the panel's
// first row: w entries of the panel's own columns, then the h rows below. The solves stream through the factor
// once per direction, bound by memory bandwidth and by dependent adds, so they are plain loops (BLAS handles a
// few right-hand sides poorly: dgemm with n = 1..3); each column of L is read from memory once and from cache
// for the further right-hand sides. Compiled for the baseline ISA and for x86-64-v3 (AVX2, FMA), chosen when
// the library loads.

//! Four doubles as one vector (an AVX2 register, or two SSE2 ones in the baseline clone); loads need not be
//! aligned, and may alias the doubles they read.
typedef double Vec4d __attribute__((vector_size(32), aligned(8), may_alias));

//! x_j -= sum_{i < h} Rr(i, j) x_{w + i} for the NB columns j0 .. j0 + NB - 1 of a panel's rectangle and R
//! right-hand sides (columns of x, leading dimension ldx): each entry of x is loaded once for the NB columns
//! and each entry of L once for the R right-hand sides, four partial sums per product (the compiler may not
//! reorder a floating-point sum itself), NB x R of them in flight to hide the adds' latency. Against one dot
//! product per column and right-hand side, which loaded both operands for every multiply-add, the 104k TF
//! frame took 72 instead of 83 ms (medians of six paired rounds of 40 frames); LAP's frames stayed the same.

template <int NB, int R>
inline __attribute__((always_inline)) void rect_dots(const double* Rr, std::size_t sh, int j0, int w, int h,
                                                     double* x, int ldx) {
  Vec4d acc[NB][R];
  for (int k = 0; k < NB; ++k)
    for (int c = 0; c < R; ++c) acc[k][c] = Vec4d{0, 0, 0, 0};
  const double* q[NB];
  for (int k = 0; k < NB; ++k) q[k] = Rr + std::size_t(j0 + k) * sh;
  const double* xs[R];
  for (int c = 0; c < R; ++c) xs[c] = x + std::size_t(c) * std::size_t(ldx) + std::size_t(w);
  int i = 0;
  for (; i + 4 <= h; i += 4) {
    Vec4d xv[R];
    for (int c = 0; c < R; ++c) xv[c] = *reinterpret_cast<const Vec4d*>(xs[c] + i);
    for (int k = 0; k < NB; ++k) {
      const Vec4d qv = *reinterpret_cast<const Vec4d*>(q[k] + i);
      for (int c = 0; c < R; ++c) acc[k][c] += qv * xv[c];
    }
  }
  for (int k = 0; k < NB; ++k)
    for (int c = 0; c < R; ++c) {
      double sum = (acc[k][c][0] + acc[k][c][2]) + (acc[k][c][1] + acc[k][c][3]);
      for (int t = i; t < h; ++t) sum += q[k][t] * xs[c][t];
      x[std::size_t(c) * std::size_t(ldx) + std::size_t(j0 + k)] -= sum;
    }
}

//! The rectangle's part of backward_panel for R right-hand sides: NB columns at a time (NB x R accumulators and
//! NB + R loads per step fit the sixteen vector registers), then the remaining columns one by one.
template <int NB, int R>
inline __attribute__((always_inline)) void rect_solve(const double* Rr, int w, int h, double* x, int ldx) {
  const std::size_t sh = std::size_t(h);
  int j = 0;
  for (; j + NB <= w; j += NB) rect_dots<NB, R>(Rr, sh, j, w, h, x, ldx);
  for (; j < w; ++j) rect_dots<1, R>(Rr, sh, j, w, h, x, ldx);
}

//! x_j /= L_jj, then x_i -= L_ij x_j below j: the rows under the panel start at zero and end as -L_rs y_s.
//! The triangle first, then the rectangle four columns at a time (one pass over x's rows per four columns of
//! L, each column read from memory once for all right-hand sides).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void forward_panel(const double* T, const double* Rr, int w,
                                                                                int h, int r, double* x, int ldx) {
  for (int j = 0; j < w; ++j) {
    const double* t = T + packed_column(j, w);  // t[i - j] = L_ij, i = j .. w - 1
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v = (xc[j] /= t[0]);
      for (int i = 1; i < w - j; ++i) xc[j + i] -= t[i] * v;
    }
  }
  const std::size_t sh = std::size_t(h);
  int j = 0;
  for (; j + 3 < w; j += 4) {
    const double *q0 = Rr + std::size_t(j) * sh, *q1 = q0 + sh, *q2 = q1 + sh, *q3 = q2 + sh;
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v0 = xc[j], v1 = xc[j + 1], v2 = xc[j + 2], v3 = xc[j + 3];
      double* xr = xc + w;
      for (int i = 0; i < h; ++i) xr[i] -= (q0[i] * v0 + q1[i] * v1) + (q2[i] * v2 + q3[i] * v3);
    }
  }
  for (; j < w; ++j) {
    const double* q = Rr + std::size_t(j) * sh;
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v = xc[j];
      double* xr = xc + w;
      for (int i = 0; i < h; ++i) xr[i] -= q[i] * v;
    }
  }
}

//! x_j = (x_j - sum_{i>j} L_ij x_i) / L_jj: the rectangle's dot products first (independent of each other,
//! the rows below are final), then the triangle bottom up.
__attribute__((target_clones("arch=x86-64-v3", "default"))) void backward_panel(const double* T, const double* Rr, int w,
                                                                                 int h, int r, double* x, int ldx) {
  if (h > 0)
    for (int c = 0; c < r;) {  // one (TF's); more than four (backward_rows4 takes two to four) three at a time
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      switch (std::min(r - c, 3)) {
        case 3: rect_solve<2, 3>(Rr, w, h, xc, ldx); c += 3; break;
        case 2: rect_solve<2, 2>(Rr, w, h, xc, ldx); c += 2; break;
        default: rect_solve<4, 1>(Rr, w, h, xc, ldx); c += 1; break;
      }
    }
  for (int j = w - 1; j >= 0; --j) {
    const double* t = T + packed_column(j, w);
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      double sum = 0;
      for (int i = 1; i < w - j; ++i) sum += t[i] * xc[j + i];
      xc[j] = (xc[j] - sum) / t[0];
    }
  }
}

//! x_j -= sum_{i < h} Rr(i, j) x_{w + i} for the NB columns from j0, x held row by row as in backward_rows4.
template <int NB>
inline __attribute__((always_inline)) void rows4_rect(const double* Rr, std::size_t sh, int j0, int w, int h,
                                                      double* x) {
  Vec4d acc[NB];
  for (int k = 0; k < NB; ++k) acc[k] = Vec4d{0, 0, 0, 0};
  const double* q = Rr + std::size_t(j0) * sh;
  const double* xb = x + 4 * std::size_t(w);
  for (int i = 0; i < h; ++i) {
    const Vec4d xi = *reinterpret_cast<const Vec4d*>(xb + 4 * std::size_t(i));
    for (int k = 0; k < NB; ++k) {
      const double l = q[std::size_t(k) * sh + std::size_t(i)];
      acc[k] += Vec4d{l, l, l, l} * xi;
    }
  }
  for (int k = 0; k < NB; ++k) *reinterpret_cast<Vec4d*>(x + 4 * std::size_t(j0 + k)) -= acc[k];
}

//! backward_panel for two to four right-hand sides held row by row: row k of x in lanes 0..3 of x + 4k (unused
//! lanes zero). Each entry of L is one multiply-add on a whole row of x, with no horizontal sums. With LAP's
//! three right-hand sides on small supernodes (most of the 104k system's) the general kernel's per-column dot
//! products were mostly reductions and tails: its frames took three times one pass over the factor at the
//! memory read rate (27 against 9 ms), TF's single right-hand side 1.1 times. The 104k LAP frame went from 26.8
//! to 20.8 ms (medians of six paired runs of 40 frames).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void backward_rows4(const double* T, const double* Rr, int w,
                                                                                 int h, double* x) {
  const std::size_t sh = std::size_t(h);
  int j = 0;
  for (; j + 8 <= w; j += 8) rows4_rect<8>(Rr, sh, j, w, h, x);
  for (; j + 4 <= w; j += 4) rows4_rect<4>(Rr, sh, j, w, h, x);
  for (; j < w; ++j) rows4_rect<1>(Rr, sh, j, w, h, x);
  auto row = [x](int i) -> Vec4d& { return *reinterpret_cast<Vec4d*>(x + 4 * std::size_t(i)); };
  for (j = w - 1; j >= 0; --j) {  // the triangle bottom up, two partial sums (the adds' latency)
    const double* t = T + packed_column(j, w);
    Vec4d s0{0, 0, 0, 0}, s1{0, 0, 0, 0};
    int i = 1;
    for (; i + 1 < w - j; i += 2) {
      s0 += Vec4d{t[i], t[i], t[i], t[i]} * row(j + i);
      s1 += Vec4d{t[i + 1], t[i + 1], t[i + 1], t[i + 1]} * row(j + i + 1);
    }
    if (i < w - j) s0 += Vec4d{t[i], t[i], t[i], t[i]} * row(j + i);
    row(j) = (row(j) - (s0 + s1)) / Vec4d{t[0], t[0], t[0], t[0]};
  }
}

//! Per-thread scratch: row -> front position map, relative indices.
struct Workspace {
  std::vector<int> map, rel;
  std::vector<double> diag;  //!< a panel's diagonal block, unpacked for dpotrf
  explicit Workspace(int n) : map(std::size_t(n), -1), diag(std::size_t(FactorBlock::kWidth) * FactorBlock::kWidth) {}
};

class MultifrontalSolver final : public LinearSolver {
 public:
  explicit MultifrontalSolver(const SolverOptions& options) : options_(options) {
    check_options(options, name());
  }

  std::string name() const override { return "multifrontal"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    const int n = int(upper.cols());
    const int b = options_.block_size > 1 && n % options_.block_size == 0 ? options_.block_size : 1;
    factored_ = false;
    values_.reset();
    base_.resize(0, 0);
    threads_ = std::clamp(worker_threads(), 1, 64);  // owner[] holds a thread index in a signed char
    S_ = analyze_blocks(upper, b, options_.ordering);
    factor_plan_ = schedule(S_, threads_, [&](int s) { return supernode_flops(S_, s); });
    // A solve reads each factor entry once per direction: its threads are balanced by entries, not flops.
    solve_plan_ = schedule(S_, threads_, [&](int s) { return double(S_.xptr[std::size_t(s) + 1] - S_.xptr[std::size_t(s)]); });
    guard_.remember(upper);
    stats_ = FactorStats{};
    stats_.n = std::size_t(n);
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.nnz_factor = S_.nnz;
    stats_.flops = S_.flops;
    stats_.ordering_used = (options_.ordering == "default" ? std::string(default_ordering(b)) : options_.ordering) +
                           (b > 1 ? fmt::format("-block{}", b) : "");
    stats_.factor_bytes = factor_bytes();
    stats_.factor_on_disk = !options_.factor_dir.empty();
    stats_.workspace_bytes = std::size_t(update_peak(S_, factor_plan_));
  }

  void factorize(const SpMat& upper_in) override { factorize_impl(upper_in, nullptr); }

  void factorize_consuming(SpMat& upper) override {
    const ClearOnExit clear{upper};
    factorize_impl(upper, &upper);
  }

 private:
  //! `consumed`: the caller's matrix (the same object as upper_in), whose memory may be handed back as the
  //! factorization no longer needs it; null to leave the matrix alone.
  void factorize_impl(const SpMat& upper_in, SpMat* consumed) {
    SpMat storage;
    const SpMat& given = prepare_factorize(*this, guard_, upper_in, storage);
    const DenseVec diag = diagonal_of(given);  // for the pivot check, before any of the matrix is released
    factored_ = false;
    iperm_.assign(S_.perm.size(), 0);
    for (std::size_t k = 0; k < S_.perm.size(); ++k) iperm_[std::size_t(S_.perm[k])] = int(k);
    SpMat permuted;
    if (!S_.perm.empty()) {  // the analysis chose an order: factor P A P^T
      // Upper triangle of P A P^T with sorted columns (the front assembly searches them).
      std::vector<Eigen::Triplet<double, int>> t;
      t.reserve(std::size_t(given.nonZeros()));
      for (int j = 0; j < given.outerSize(); ++j)
        for (SpMat::InnerIterator it(given, j); it; ++it) {
          const int a = iperm_[std::size_t(it.row())], c = iperm_[std::size_t(j)];
          t.emplace_back(std::min(a, c), std::max(a, c), it.value());
        }
      permuted.resize(given.rows(), given.cols());
      permuted.setFromTriplets(t.begin(), t.end());
      if (consumed) *consumed = SpMat();  // the permuted copy holds all the factorization reads
    }
    const SpMat& A = S_.perm.empty() ? given : permuted;
    // Pages of A whose columns are consumed may be returned: ours (a copy), or the caller's when consumed.
    const bool may_release = &A != &upper_in || consumed != nullptr;
    base_.resize(0, 0);  // a new factor invalidates the rest-pose forward substitution
    values_ = options_.factor_dir.empty() ? Mapping(S_.xptr.back(), "the factor")
                                          : Mapping::on_file(S_.xptr.back(), "the factor", options_.factor_dir);
    pivots_.assign(std::size_t(S_.n), 0.0);
    updates_.clear();
    updates_.resize(std::size_t(S_.nsuper()));
    failed_column_ = -1;
    std::atomic<bool> ok{true};
    std::mutex top_mutex;
    parallel_subtrees([&](std::size_t t) {
      Workspace ws(S_.n);
      ColumnRelease release(A, may_release);
      for (int root : factor_plan_.subtrees[t]) {
        release.start(S_.col0[std::size_t(S_.first[std::size_t(root)])]);
        for (int s = S_.first[std::size_t(root)]; s <= root; ++s) {
          if (!ok.load(std::memory_order_relaxed) || !factor_supernode(A, s, ws)) {
            ok = false;
            return;
          }
          release_block(s);
          release.dead_before(S_.col0[std::size_t(s) + 1], s == root);
        }
        // Hand the subtree's update matrix to its (top) parent now rather than when the top phase reaches it:
        // otherwise every subtree root's update is resident at once when the top phase starts (53 MB of the
        // 104k TF system's peak). Threads finish their subtrees at different times, so this rarely waits.
        if (const int parent = S_.parent[std::size_t(root)]; parent >= 0) {
          std::lock_guard<std::mutex> lock(top_mutex);
          assemble_child(root, parent, ws);
        }
      }
    });
    if (ok) {
      Workspace ws(S_.n);
      ColumnRelease release(A, may_release);
      for (int s : factor_plan_.top) {
        release.start(S_.col0[std::size_t(s)]);
        if (!factor_supernode(A, s, ws)) break;
        release_block(s);
        release.dead_before(S_.col0[std::size_t(s) + 1], true);
      }
    }
    updates_.clear();
    if (failed_column_ >= 0) {
      values_.reset();
      const int k = int(failed_column_);
      const int orig = S_.perm.empty() ? k : S_.perm[std::size_t(k)];
      throw SolverError(fmt::format("multifrontal: matrix not positive definite (failed at column {} of {}, "
                                    "unknown {})",
                                    k, S_.n, orig));
    }
    stats_.min_pivot_ratio = check_pivots(pivots_, S_.perm.empty() ? nullptr : S_.perm.data(), diag, name(),
                                          options_.pivot_singularity_test);
    factored_ = true;
    stats_.factor_bytes = factor_bytes();
  }

  //! Hands A's pages back to the OS as its columns die, in one thread's run of consecutive supernodes. Column i
  //! is read only by its own supernode and that supernode's descendants, all numbered below it, so after
  //! supernode s every column of the run up to s's last one is dead. Whole pages only (a page at either end of
  //! the run may hold another run's live columns), in steps of at least a megabyte; dead pages read as zero.
  class ColumnRelease {
   public:
    ColumnRelease(const SpMat& A, bool enabled)
        : A_(A), on_(enabled && std::size_t(A.nonZeros()) * sizeof(double) >= (std::size_t(16) << 20)) {}
    //! A run starts at column `col`.
    void start(int col) {
      if (!on_) return;
      for (int a = 0; a < 2; ++a) done_[a] = page_up(at(a, col));
    }
    //! Columns before `col` are dead; `all`: release what is whole-page dead now, however little.
    void dead_before(int col, bool all = false) {
      if (!on_) return;
      for (int a = 0; a < 2; ++a) {
        const std::uintptr_t end = page_down(at(a, col));
        if (end > done_[a] && (all || end - done_[a] >= (std::uintptr_t(1) << 20))) {
          ::madvise(reinterpret_cast<void*>(done_[a]), end - done_[a], MADV_DONTNEED);
          done_[a] = end;
        }
      }
    }

   private:
    std::uintptr_t at(int a, int col) const {  // a = 0: values, 1: row indices
      const std::size_t k = std::size_t(A_.outerIndexPtr()[col]);
      return a == 0 ? reinterpret_cast<std::uintptr_t>(A_.valuePtr() + k)
                    : reinterpret_cast<std::uintptr_t>(A_.innerIndexPtr() + k);
    }
    const SpMat& A_;
    bool on_;
    std::uintptr_t done_[2] = {0, 0};
  };

 public:

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(S_.n), name());
    load_rhs(B);
    forward_all();
    backward_all();
    store_solution(X);
  }

  void set_base_rhs(const DenseMat& B0, const std::vector<int>& rows) override {
    if (!factored_) throw SolverError(fmt::format("{}: set_base_rhs() before a successful factorize()", name()));
    check_rhs(B0, Index(S_.n), name());
    base_.resize(0, 0);
    std::vector<char> changing(std::size_t(S_.n), 0);
    for (int i : rows) {
      if (i < 0 || i >= S_.n) throw SolverError(fmt::format("{}: set_base_rhs(): row {} out of range", name(), i));
      changing[std::size_t(i)] = 1;
    }
    // Supernodes the changing rows reach: those holding them and all their ancestors (ascending = postorder).
    std::vector<int> super_of(std::size_t(S_.n));
    for (int s = 0; s < S_.nsuper(); ++s)
      std::fill(super_of.begin() + S_.col0[std::size_t(s)], super_of.begin() + S_.col0[std::size_t(s) + 1], s);
    std::vector<char> reached(std::size_t(S_.nsuper()), 0);
    for (int i : rows)
      for (int s = super_of[std::size_t(iperm(i))]; s >= 0 && !reached[std::size_t(s)]; s = S_.parent[std::size_t(s)])
        reached[std::size_t(s)] = 1;
    reach_.clear();
    reach_columns_.clear();
    for (int s = 0; s < S_.nsuper(); ++s)
      if (reached[std::size_t(s)]) {
        reach_.push_back(s);
        for (int j = S_.col0[std::size_t(s)]; j < S_.col0[std::size_t(s) + 1]; ++j) reach_columns_.push_back(j);
      }
    load_rhs(B0);
    forward_all();
    y0_ = y_;
    changing_ = std::move(changing);
    changing_rows_ = rows;
    base_ = B0;
  }

  void solve_changed(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(S_.n), name());
    if (base_.rows() != B.rows() || base_.cols() != B.cols() || !matches_base_outside_changing_rows(B)) {
      solve(B, X);
      return;
    }
    // L z = P (B - B0) has z = 0 outside the reached supernodes; y = y0 + z.
    y_ = y0_;
    for (int j : reach_columns_) y_.row(j).setZero();
    for (int i : changing_rows_)
      for (Index c = 0; c < B.cols(); ++c) y_(iperm(i), c) += B(i, c) - base_(i, c);
    std::vector<double> tmp;
    for (int s : reach_) forward(s, -1, tmp);
    for (int j : reach_columns_) y_.row(j) += y0_.row(j);
    backward_all();
    store_solution(X);
  }

  FactorStats stats() const override { return stats_; }

 private:
  int iperm(int i) const { return iperm_.empty() ? i : iperm_[std::size_t(i)]; }

  //! y_ := P B (row-major).
  void load_rhs(const DenseMat& B) {
    const Index n = S_.n, r = B.cols();
    y_.resize(n, r);
    for (Index c = 0; c < r; ++c)
      for (Index k = 0; k < n; ++k) y_(k, c) = B(S_.perm.empty() ? k : S_.perm[std::size_t(k)], c);
  }

  //! X := P^T y_.
  void store_solution(DenseMat& X) const {
    const Index n = S_.n, r = y_.cols();
    X.resize(n, r);
    for (Index c = 0; c < r; ++c)
      for (Index k = 0; k < n; ++k) X(S_.perm.empty() ? k : S_.perm[std::size_t(k)], c) = y_(k, c);
    check_finite_result(X, name());
  }

  //! y_ := L^{-1} y_: subtrees in parallel (contributions to top columns collected per thread), then the top.
  void forward_all() {
    const Index n = S_.n, r = y_.cols();
    const std::size_t T = solve_plan_.subtrees.size();
    acc_.resize(T);
    for (auto& a : acc_) {
      a.resize(n, r);
      for (int j : solve_plan_.top_columns) a.row(j).setZero();
    }
    parallel_subtrees([&](std::size_t t) {
      std::vector<double> tmp;
      for (int root : solve_plan_.subtrees[t])
        for (int s = S_.first[std::size_t(root)]; s <= root; ++s) forward(s, int(t), tmp);
    });
    for (std::size_t t = 0; t < T; ++t)
      for (int j : solve_plan_.top_columns) y_.row(j) += acc_[t].row(j);
    std::vector<double> tmp;
    for (int s : solve_plan_.top) forward(s, -1, tmp);
  }

  //! y_ := L^{-T} y_: the top first, then the subtrees in parallel.
  void backward_all() {
    std::vector<double> tmp;
    for (auto it = solve_plan_.top.rbegin(); it != solve_plan_.top.rend(); ++it) backward(*it, tmp);
    parallel_subtrees([&](std::size_t t) {
      std::vector<double> tmp_t;
      for (auto it = solve_plan_.subtrees[t].rbegin(); it != solve_plan_.subtrees[t].rend(); ++it)
        for (int s = *it; s >= S_.first[std::size_t(*it)]; --s) backward(s, tmp_t);
    });
  }

  bool matches_base_outside_changing_rows(const DenseMat& B) const {
    for (Index c = 0; c < B.cols(); ++c)
      for (Index k = 0; k < B.rows(); ++k)
        if (!changing_[std::size_t(k)] && B(k, c) != base_(k, c)) return false;
    return true;
  }

  //! fn(t) for every thread t, on threads when there are several; the BLAS runs single-threaded meanwhile.
  template <class Fn>
  void parallel_subtrees(Fn fn) {
    const std::size_t T = factor_plan_.subtrees.size();  // the same thread count in both plans
    if (T <= 1) {
      if (T == 1) fn(0);
      return;
    }
    const int saved = blas_threads().get();
    blas_threads().set(1);
    struct Restore {
      int n;
      ~Restore() { blas_threads().set(n); }
    } restore{saved};
    run_on_threads(int(T), [&](int t) { fn(std::size_t(t)); });
  }

  //! Front column j of supernode s's FactorBlock L: entries of rows j .. split - 1 are tri[row], those of
  //! rows split .. m - 1 are rect[row - split] (rows as front positions).
  struct FrontColumn {
    double *tri, *rect;
    int split;
  };
  static FrontColumn front_column(const FactorBlock& L, int j) {
    const int p = j / FactorBlock::kWidth, c0 = L.c0(p), w = L.width(p);
    return {L.tri(p) + packed_column(j - c0, w) - std::size_t(j),
            L.rect(p) + std::size_t(j - c0) * std::size_t(L.height(p)), c0 + w};
  }

  //! Which columns of a child's update matrix an extend-add moves: those landing in the parent's own columns
  //! (its factor block), those landing in its update matrix, or both.
  enum Part { kPivot = 1, kUpdate = 2, kBoth = 3 };

  //! Extend-add of `part` of child c's update matrix into supernode p's factor block and update matrix (with
  //! kUpdate, p's update matrix is allocated zeroed here if it has none yet); frees the child's matrix once
  //! nothing of it is left to move. The caller makes sure no other thread works on p meanwhile.
  void assemble_child(int c, int p, Workspace& ws, Part part = kBoth) {
    const int nc = S_.ncols(p), m = S_.nrows(p), nr = m - nc;
    const int* R = S_.rows.data() + S_.rptr[std::size_t(p)];
    for (int k = 0; k < m; ++k) ws.map[std::size_t(R[k])] = k;
    const FactorBlock L{values_.get() + S_.xptr[std::size_t(p)], m, nc};
    const int ncc = S_.ncols(c), nrc = S_.nrows(c) - ncc;
    const int* Rc = S_.rows.data() + S_.rptr[std::size_t(c)] + ncc;
    ws.rel.resize(std::size_t(nrc));
    for (int k = 0; k < nrc; ++k) ws.rel[std::size_t(k)] = ws.map[std::size_t(Rc[k])];
    const int* rel = ws.rel.data();
    // Rows ascend, so the columns landing in p's own columns come first.
    const int jsplit = int(std::lower_bound(rel, rel + nrc, nc) - rel);
    const UpdateBlock& Uc = updates_[std::size_t(c)];
    if (part & kPivot)
      for (int jj = 0; jj < jsplit; ++jj) {
        const double* src = Uc.col(jj) - jj;  // src[ii] = entry (ii, jj)
        const FrontColumn col = front_column(L, rel[jj]);
        int ii = jj;
        for (; ii < nrc && rel[ii] < col.split; ++ii) col.tri[rel[ii]] += src[ii];
        for (; ii < nrc; ++ii) col.rect[rel[ii] - col.split] += src[ii];
      }
    if ((part & kUpdate) && jsplit < nrc) {
      UpdateBlock& U = updates_[std::size_t(p)];
      if (!U) U = UpdateBlock(nr, true);
      for (int jj = jsplit; jj < nrc; ++jj) {
        const int lj = rel[jj] - nc;
        const double* src = Uc.col(jj) - jj;
        double* dst = U.col(lj) - lj - nc;  // dst[k] = entry (k - nc, lj) of U
        for (int ii = jj; ii < nrc; ++ii) dst[rel[ii]] += src[ii];
      }
    }
    if ((part & kUpdate) || jsplit == nrc) updates_[std::size_t(c)] = UpdateBlock();
  }

  //! Assembles and factors the front of supernode s; false (and failed_column_ set) when a pivot is not positive.
  //! Its FactorBlock starts as the mapping's zero pages, and may already hold some children's updates.
  //! When s's update matrix is a fresh heap block, the children's entries for it are added after s's own
  //! product has written it (beta = 0), so it is never zero-filled: that fill took a fifth of the extend-add
  //! time on the 104k TF system. Mapped update matrices come zeroed from the kernel anyway: they take the
  //! children whole first, so that the largest children's matrices are not kept any longer.
  bool factor_supernode(const SpMat& A, int s, Workspace& ws) {
    const int f = S_.col0[std::size_t(s)], nc = S_.ncols(s), m = S_.nrows(s), nr = m - nc;
    const FactorBlock L{values_.get() + S_.xptr[std::size_t(s)], m, nc};
    const int* kids = S_.child.data() + S_.cptr[std::size_t(s)];
    const int nkids = S_.cptr[std::size_t(s) + 1] - S_.cptr[std::size_t(s)];
    // Not begun by children assembled early (top supernodes), and not mapped.
    const bool fresh_heap = nr > 0 && !updates_[std::size_t(s)] && !UpdateBlock::mapped(nr);
    for (int q = 0; q < nkids; ++q)
      if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, fresh_heap ? kPivot : kBoth);
    const int* R = S_.rows.data() + S_.rptr[std::size_t(s)];
    for (int k = 0; k < m; ++k) ws.map[std::size_t(R[k])] = k;
    // Matrix entries A(i, j), j in this supernode, i >= j: the upper triangle holds them as A(j, i) in
    // column i, and every such i is a row of the front.
    const int* Ap = A.outerIndexPtr();
    const int* Ai = A.innerIndexPtr();
    const double* Ax = A.valuePtr();
    for (int k = 0; k < m; ++k) {
      const int i = R[k];
      const int* b = Ai + Ap[i];
      const int* e = Ai + Ap[i + 1];
      const int last = std::min(i, f + nc - 1);
      for (const int* p = std::lower_bound(b, e, f); p != e && *p <= last; ++p) {
        const FrontColumn col = front_column(L, *p - f);
        (k < col.split ? col.tri[k] : col.rect[k - col.split]) += Ax[p - Ai];
      }
    }
    // Left-looking over the panels: apply the earlier panels, factor the diagonal block, solve the rectangle.
    const double one = 1.0, minus_one = -1.0;
    const int K = FactorBlock::kWidth;
    double* D = ws.diag.data();
    for (int q = 0; q < L.panels(); ++q) {
      const int c0 = L.c0(q), w = L.width(q), h = L.height(q);
      double* T = L.tri(q);
      for (int j = 0; j < w; ++j)
        std::copy(T + packed_column(j, w), T + packed_column(j + 1, w), D + std::size_t(j) * std::size_t(w + 1));
      for (int p = 0; p < q; ++p) {
        const double* Rp = L.rect(p) + (c0 - L.c0(p) - K);  // panel p's rows from c0 down
        const int ldp = L.height(p);
        dsyrk_("L", "N", &w, &K, &minus_one, Rp, &ldp, &one, D, &w, 1, 1);
        if (h > 0) dgemm_("N", "T", &h, &w, &K, &minus_one, Rp + w, &ldp, Rp, &ldp, &one, L.rect(q), &h, 1, 1);
      }
      int info = 0;
      dpotrf_("L", &w, D, &w, &info, 1);
      if (info != 0) {
        std::int64_t expected = -1;
        failed_column_.compare_exchange_strong(expected, std::int64_t(f + c0 + std::max(info, 1) - 1));
        return false;
      }
      if (h > 0) dtrsm_("R", "L", "T", "N", &h, &w, &one, D, &w, L.rect(q), &h, 1, 1, 1, 1);
      for (int j = 0; j < w; ++j) {
        const double l = D[std::size_t(j) * std::size_t(w + 1)];
        pivots_[std::size_t(f + c0 + j)] = l * l;
      }
      for (int j = 0; j < w; ++j)
        std::copy(D + std::size_t(j) * std::size_t(w + 1), D + std::size_t(j + 1) * std::size_t(w),
                  T + packed_column(j, w));
    }
    // Update matrix: U -= B B^T, B the rows below the supernode's columns, panel by panel of both; a fresh
    // heap U is written by the first panel's product (beta = 0), then takes the children's remaining entries.
    if (nr > 0) {
      UpdateBlock U =
          updates_[std::size_t(s)] ? std::move(updates_[std::size_t(s)]) : UpdateBlock(nr, !fresh_heap);
      const double zero = 0.0;
      for (int p = 0; p < L.panels(); ++p) {
        const int wp = L.width(p), ldp = L.height(p);
        const double* B = L.rect(p) + (nc - L.c0(p) - wp);
        const double* beta = fresh_heap && p == 0 ? &zero : &one;
        for (int u = 0; u < U.panels(); ++u) {
          const int u0 = u * UpdateBlock::kWidth, wu = U.width(u), ldu = nr - u0, below = ldu - wu;
          dsyrk_("L", "N", &wu, &wp, &minus_one, B + u0, &ldp, beta, U.panel(u), &ldu, 1, 1);
          if (below > 0)
            dgemm_("N", "T", &below, &wu, &wp, &minus_one, B + u0 + wu, &ldp, B + u0, &ldp, beta, U.panel(u) + wu,
                   &ldu, 1, 1);
        }
      }
      updates_[std::size_t(s)] = std::move(U);
      if (fresh_heap)
        for (int q = 0; q < nkids; ++q)
          if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, kUpdate);
    }
    return true;
  }

  //! y_s := L_ss^{-1} y_s, then y_rows -= L_rs y_s. Thread t adds to columns it does not own in acc_[t].
  void forward(int s, int t, std::vector<double>& tmp) {
    const int f = S_.col0[std::size_t(s)], nc = S_.ncols(s), m = S_.nrows(s);
    const int* R = S_.rows.data() + S_.rptr[std::size_t(s)];
    const int r = int(y_.cols());
    const std::size_t sm = std::size_t(m), sr = std::size_t(r);
    double* y = y_.data();
    tmp.assign(sm * sr, 0.0);
    for (int k = 0; k < nc; ++k)
      for (int c = 0; c < r; ++c) tmp[std::size_t(c) * sm + std::size_t(k)] = y[std::size_t(f + k) * sr + std::size_t(c)];
    const FactorBlock L{values_.get() + S_.xptr[std::size_t(s)], m, nc};
    for (int p = 0; p < L.panels(); ++p)
      forward_panel(L.tri(p), L.rect(p), L.width(p), L.height(p), r, tmp.data() + L.c0(p), m);
    release_block(s);
    for (int k = 0; k < nc; ++k)
      for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = tmp[std::size_t(c) * sm + std::size_t(k)];
    double* acc = t >= 0 ? acc_[std::size_t(t)].data() : nullptr;
    for (int k = nc; k < m; ++k) {
      const int i = R[k];
      double* dst = (t < 0 || solve_plan_.owner[std::size_t(i)] == t ? y : acc) + std::size_t(i) * sr;
      for (int c = 0; c < r; ++c) dst[c] += tmp[std::size_t(c) * sm + std::size_t(k)];
    }
  }

  //! y_s -= L_rs^T y_rows, then y_s := L_ss^{-T} y_s.
  void backward(int s, std::vector<double>& tmp) {
    const int f = S_.col0[std::size_t(s)], nc = S_.ncols(s), m = S_.nrows(s);
    const int* R = S_.rows.data() + S_.rptr[std::size_t(s)];
    const int r = int(y_.cols());
    const std::size_t sm = std::size_t(m), sr = std::size_t(r);
    double* y = y_.data();
    const FactorBlock L{values_.get() + S_.xptr[std::size_t(s)], m, nc};
    if (r >= 2 && r <= 4) {  // rows of x as vectors (backward_rows4); the general kernel otherwise
      tmp.resize(sm * 4);
      double* x = tmp.data();
      for (int k = 0; k < m; ++k) {  // plain loops: a few doubles a row, not worth a library call
        const double* src = y + std::size_t(k < nc ? f + k : R[k]) * sr;
        for (int c = 0; c < 4; ++c) x[4 * std::size_t(k) + std::size_t(c)] = c < r ? src[c] : 0.0;
      }
      for (int p = L.panels() - 1; p >= 0; --p)
        backward_rows4(L.tri(p), L.rect(p), L.width(p), L.height(p), x + 4 * std::size_t(L.c0(p)));
      release_block(s);
      for (int k = 0; k < nc; ++k)
        for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = x[4 * std::size_t(k) + std::size_t(c)];
      return;
    }
    tmp.resize(sm * sr);
    for (int k = 0; k < m; ++k) {
      const double* src = y + std::size_t(k < nc ? f + k : R[k]) * sr;
      for (int c = 0; c < r; ++c) tmp[std::size_t(c) * sm + std::size_t(k)] = src[c];
    }
    for (int p = L.panels() - 1; p >= 0; --p)
      backward_panel(L.tri(p), L.rect(p), L.width(p), L.height(p), r, tmp.data() + L.c0(p), m);
    release_block(s);
    for (int k = 0; k < nc; ++k)
      for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = tmp[std::size_t(c) * sm + std::size_t(k)];
  }

  //! Out of core: supernode s's FactorBlock leaves the resident set (done with it for now).
  void release_block(int s) const {
    values_.release(values_.get() + S_.xptr[std::size_t(s)], values_.get() + S_.xptr[std::size_t(s) + 1]);
  }

  std::size_t factor_bytes() const {
    const std::size_t ints = S_.perm.size() + S_.col0.size() + S_.rptr.size() + S_.rows.size() + S_.parent.size() +
                             S_.first.size() + S_.cptr.size() + S_.child.size();
    return S_.xptr.back() * sizeof(double) + ints * sizeof(int) + S_.xptr.size() * sizeof(std::size_t);
  }

  SolverOptions options_;
  Symbolic S_;
  Plan factor_plan_, solve_plan_;
  int threads_ = 1;
  Mapping values_;  //!< the FactorBlocks of all supernodes
  std::vector<double> pivots_;  //!< L_jj^2 per column, kept as the factorization goes (no pass over the factor)
  std::vector<UpdateBlock> updates_;  //!< update matrix of each supernode until its parent takes it
  std::atomic<std::int64_t> failed_column_{-1};
  // Row-major: a row gathered or scattered in a solve is one cache line for all its right-hand sides.
  using RowMajorMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajorMat y_;
  std::vector<RowMajorMat> acc_;
  std::vector<int> iperm_;  //!< inverse of S_.perm (empty: identity)
  // set_base_rhs(): the base right-hand side, its forward substitution, the rows that may change and the
  // supernodes (and their columns) they reach.
  DenseMat base_;
  RowMajorMat y0_;
  std::vector<char> changing_;
  std::vector<int> changing_rows_, reach_, reach_columns_;
  PatternGuard guard_;
  FactorStats stats_;
  bool factored_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_multifrontal(const SolverOptions& options) {
  return std::make_unique<MultifrontalSolver>(options);
}

}  // namespace db
