//! CHOLMOD backends: supernodal LL^T ("cholmod_supernodal") and simplicial LDL^T ("cholmod_simplicial_ldlt").
#include <algorithm>
#include <cstring>
#include <vector>

#include <amd.h>
#include <cholmod.h>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

const char* status_name(int status) {
  switch (status) {
    case CHOLMOD_OK: return "CHOLMOD_OK";
    case CHOLMOD_NOT_INSTALLED: return "CHOLMOD_NOT_INSTALLED";
    case CHOLMOD_OUT_OF_MEMORY: return "CHOLMOD_OUT_OF_MEMORY";
    case CHOLMOD_TOO_LARGE: return "CHOLMOD_TOO_LARGE (integer overflow)";
    case CHOLMOD_INVALID: return "CHOLMOD_INVALID";
    case CHOLMOD_GPU_PROBLEM: return "CHOLMOD_GPU_PROBLEM";
    case CHOLMOD_NOT_POSDEF: return "CHOLMOD_NOT_POSDEF";
    case CHOLMOD_DSMALL: return "CHOLMOD_DSMALL";
    default: return "unknown CHOLMOD status";
  }
}

const char* ordering_name(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    case CHOLMOD_POSTORDERED: return "natural-postordered";
    default: return "unknown";
  }
}

//! Zero-copy CHOLMOD view of the (compressed) upper triangle; stype = +1 makes CHOLMOD read only it.
cholmod_sparse sparse_view(const SpMat& upper) {
  return cholmod_upper_view(std::size_t(upper.cols()), upper.outerIndexPtr(), upper.innerIndexPtr(), upper.valuePtr());
}

cholmod_dense dense_view(const DenseMat& B) {
  return cholmod_dense_view(std::size_t(B.rows()), std::size_t(B.cols()), B.data());
}

//! Fill-reducing ordering ("amd", "metis", "nesdis") of the block graph, expanded to the unknowns
//! (perm[b*i + c] = b*p[i] + c): the graph is ~b^2 times smaller, so ordering it costs a fraction.
std::vector<int> block_permutation(const BlockGraph& g, int b, const std::string& method, cholmod_common& cc) {
  const std::size_t nb = std::size_t(g.nb);
  std::vector<int> P(nb);
  if (method == "amd") {
    double info[AMD_INFO];
    const int status = amd_order(g.nb, g.Ap.data(), g.Ai.data(), P.data(), nullptr, info);
    if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED)
      throw SolverError(fmt::format("amd_order on the {0}x{0} block graph failed (status {1})", g.nb, status));
  } else if (method == "metis") {
    P = metis_permutation({g.nb, g.Ap.data(), g.Ai.data()});  // the project's METIS (solvers/graph_ordering)
  } else {
    // Pattern-only symmetric view (stype = 1 reads the upper part of the full adjacency).
    cholmod_sparse G = cholmod_upper_view(nb, g.Ap.data(), g.Ai.data(), nullptr);
    std::vector<int> cparent(nb), cmember(nb);
    if (cholmod_nested_dissection(&G, nullptr, 0, P.data(), cparent.data(), cmember.data(), &cc) < 0 ||
        cc.status < CHOLMOD_OK)
      throw SolverError(fmt::format("CHOLMOD {} on the {}x{} block graph failed: {}", method, g.nb, g.nb,
                                    status_name(cc.status)));
  }
  std::vector<int> perm(nb * std::size_t(b));
  for (std::size_t i = 0; i < nb; ++i)
    for (int c = 0; c < b; ++c) perm[std::size_t(b) * i + std::size_t(c)] = b * P[i] + c;
  return perm;
}

class CholmodSolver final : public LinearSolver {
 public:
  CholmodSolver(bool supernodal, const SolverOptions& options) : supernodal_(supernodal), options_(options) {
    check_options(options, name());
    cholmod_start(&cc_);
    cc_.print = 0;  // failures surface as SolverError, not as stderr chatter
    cc_.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    cc_.final_ll = supernodal;  // supernodal is LL^T anyway; simplicial stays LDL^T
  }
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;
  ~CholmodSolver() override {
    free_factor();
    if (X_) cholmod_free_dense(&X_, &cc_);
    if (Y_) cholmod_free_dense(&Y_, &cc_);
    if (E_) cholmod_free_dense(&E_, &cc_);
    cholmod_finish(&cc_);
  }

  std::string name() const override { return supernodal_ ? "cholmod_supernodal" : "cholmod_simplicial_ldlt"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    free_factor();
    const int n = int(upper.cols());
    const int b = options_.block_size;
    // The block path is taken for every ordering but natural; "default" then mimics CHOLMOD's own
    // rule on the block graph: AMD, plus METIS when AMD's fill is high, keeping the smaller nnz(L).
    const bool blocked = b > 1 && n % b == 0 && options_.ordering != "natural";
    cholmod_sparse A = sparse_view(upper);
    cc_.postorder = true;
    std::string used;
    if (blocked) {
      try {  // free partial state if the analysis throws
        const BlockGraph g = block_graph(upper, b);
        auto analyze_given = [&](const std::string& method) {
          std::vector<int> perm = block_permutation(g, b, method, cc_);
          cc_.nmethods = 1;
          cc_.method[0].ordering = CHOLMOD_GIVEN;
          cholmod_factor* L = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cc_);
          if (L && cc_.status < CHOLMOD_OK) cholmod_free_factor(&L, &cc_);
          if (!L)
            throw SolverError(fmt::format("{}: cholmod_analyze_p failed: {}", name(), status_name(cc_.status)));
          return L;
        };
        used = options_.ordering == "default" ? "amd" : options_.ordering;
        L_ = analyze_given(used);
        double lnz = cc_.lnz, fl = cc_.fl;
        if (options_.ordering == "default" && fl / lnz >= 500 && lnz / double(upper.nonZeros()) >= 5) {
          cholmod_factor* Lm = nullptr;
          try {
            Lm = analyze_given("metis");
          } catch (const SolverError&) {  // METIS unavailable or failed: AMD's ordering stands
          }
          if (Lm && cc_.lnz < lnz) {
            cholmod_free_factor(&L_, &cc_);
            L_ = Lm;
            lnz = cc_.lnz;
            fl = cc_.fl;
            used = "metis";
          } else if (Lm) {
            cholmod_free_factor(&Lm, &cc_);
          }
        }
        cc_.lnz = lnz;
        cc_.fl = fl;
        used = fmt::format("{}-block{}", used, b);
      } catch (...) {
        free_factor();
        throw;
      }
    } else {
      if (options_.ordering == "default") {
        cc_.nmethods = 0;  // CHOLMOD's default: AMD, METIS too when AMD's fill is high
      } else {
        cc_.nmethods = 1;
        cc_.method[0].ordering = cholmod_ordering_code(options_.ordering);
      }
      L_ = cholmod_analyze(&A, &cc_);
      if (!L_ || cc_.status < CHOLMOD_OK)
        throw SolverError(fmt::format("{}: cholmod_analyze failed: {}", name(), status_name(cc_.status)));
      used = ordering_name(L_->ordering);
    }
    guard_.remember(upper);
    stats_ = FactorStats{};
    stats_.n = std::size_t(n);
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.nnz_factor = std::size_t(cc_.lnz);
    stats_.flops = cc_.fl;
    stats_.ordering_used = used;
    stats_.factor_bytes = factor_bytes();
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    if (!L_)
      analyze(upper);
    else
      guard_.check(upper, name());
    check_finite_values(upper, name());
    factored_ = false;
    cholmod_sparse A = sparse_view(upper);
    {
      const OpenMpSerial serial;  // the BLAS gets the cores (solver_util.h)
      cholmod_factorize(&A, L_, &cc_);
    }
    const std::size_t n = L_->n;
    if (cc_.status == CHOLMOD_NOT_POSDEF || L_->minor < n)
      throw SolverError(fmt::format("CHOLMOD: matrix not positive definite (failed at column {} of {})",
                                    std::size_t(L_->minor), n));
    if (cc_.status < CHOLMOD_OK)
      throw SolverError(fmt::format("{}: cholmod_factorize failed: {}", name(), status_name(cc_.status)));
    // LDL^T succeeds on indefinite matrices, and a singular PSD matrix may factor with rounding-noise
    // pivots; both would give garbage solutions, so inspect the pivots.
    stats_.min_pivot_ratio = check_pivots(pivots(), static_cast<const int*>(L_->Perm), upper, "CHOLMOD",
                                          options_.pivot_singularity_test);
    stats_.factor_bytes = factor_bytes();
    factored_ = true;
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(L_->n), name());
    cholmod_dense Bv = dense_view(B);
    // Reused X/Y/E workspaces: no allocation per frame once the RHS width is stable.
    if (!cholmod_solve2(CHOLMOD_A, L_, &Bv, nullptr, &X_, nullptr, &Y_, &E_, &cc_) || !X_)
      throw SolverError(fmt::format("{}: cholmod_solve2 failed: {}", name(), status_name(cc_.status)));
    X.resize(B.rows(), B.cols());
    const double* x = static_cast<const double*>(X_->x);
    for (Eigen::Index c = 0; c < B.cols(); ++c)
      std::memcpy(X.col(c).data(), x + std::size_t(c) * X_->d, sizeof(double) * std::size_t(B.rows()));
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 private:
  void free_factor() {
    if (L_) cholmod_free_factor(&L_, &cc_);
    factored_ = false;
  }

  //! Pivots in factor order: D for LDL^T, diag(L)^2 for LL^T (simplicial or supernodal layout).
  std::vector<double> pivots() const {
    const std::size_t n = L_->n;
    std::vector<double> d(n);
    const double* Lx = static_cast<const double*>(L_->x);
    if (L_->is_super) {
      const int* super = static_cast<const int*>(L_->super);
      const int* pi = static_cast<const int*>(L_->pi);
      const int* px = static_cast<const int*>(L_->px);
      for (std::size_t s = 0; s < L_->nsuper; ++s) {
        const int nsrow = pi[s + 1] - pi[s];
        for (int j = super[s]; j < super[s + 1]; ++j) {
          const int c = j - super[s];
          const double l = Lx[std::size_t(px[s]) + std::size_t(c) + std::size_t(c) * std::size_t(nsrow)];
          d[std::size_t(j)] = l * l;
        }
      }
    } else {
      const int* Lp = static_cast<const int*>(L_->p);
      for (std::size_t j = 0; j < n; ++j) d[j] = L_->is_ll ? Lx[Lp[j]] * Lx[Lp[j]] : Lx[Lp[j]];
    }
    return d;
  }

  //! Bytes of every array the factor holds (int indices: itype is CHOLMOD_INT here).
  std::size_t factor_bytes() const {
    if (!L_) return 0;
    const std::size_t ib = L_->itype == CHOLMOD_LONG ? 8 : 4;
    const std::size_t n = L_->n;
    std::size_t bytes = 2 * n * ib;  // Perm, ColCount
    if (L_->IPerm) bytes += n * ib;
    if (L_->is_super) {
      bytes += 3 * (L_->nsuper + 1) * ib + L_->ssize * ib;  // super, pi, px; s
      if (L_->x) bytes += L_->xsize * sizeof(double);
    } else if (L_->x) {
      bytes += (n + 1) * ib + L_->nzmax * (ib + sizeof(double)) + n * ib + 2 * (n + 2) * ib;  // p, i+x, nz, next/prev
    }
    return bytes;
  }

  bool supernodal_;
  SolverOptions options_;
  cholmod_common cc_{};
  cholmod_factor* L_ = nullptr;
  cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
  PatternGuard guard_;
  FactorStats stats_;
  bool factored_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_cholmod(bool supernodal, const SolverOptions& options) {
  return std::make_unique<CholmodSolver>(supernodal, options);
}

}  // namespace db
