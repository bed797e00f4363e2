#include "solvers/multifrontal/matrix_chunk.h"

#include <algorithm>
#include <mutex>

#include "solvers/base/resources.h"

namespace db::multifrontal {

int MatrixChunk::run_end(const Symbolic& S, int s0, int last) {
  constexpr int kColumns = 2048;  // about 1.5 MB of TF's entries: the buffer stays small
  int s = s0;
  while (s < last && S.col0[std::size_t(s) + 2] - S.col0[std::size_t(s0)] <= kColumns) ++s;
  return s;
}

void MatrixChunk::load(const SpMat& upper, const std::vector<int>& counts, const Symbolic& S, int s0, int s1) {
  c0_ = S.col0[std::size_t(s0)];
  const int c1 = S.col0[std::size_t(s1) + 1];
  if (mark_.size() != std::size_t(S.n)) mark_.assign(std::size_t(S.n), 0);
  if (++stamp_ == 0) {  // wrapped: start the stamps over
    std::fill(mark_.begin(), mark_.end(), 0);
    stamp_ = 1;
  }
  outside_.clear();
  for (int s = s0; s <= s1; ++s)
    for (int k = S.rptr[std::size_t(s)]; k < S.rptr[std::size_t(s) + 1]; ++k)
      if (const int i = S.rows[std::size_t(k)]; i >= c1 && mark_[std::size_t(i)] != stamp_) {
        mark_[std::size_t(i)] = stamp_;
        outside_.push_back(i);
      }
  std::sort(outside_.begin(), outside_.end());
  const int* Ai = upper.innerIndexPtr();
  const double* Ax = upper.valuePtr();
  ptr_.assign(std::size_t(c1 - c0_) + 1, 0);
  for (int j = c0_; j < c1; ++j) ptr_[std::size_t(j - c0_) + 1] = ptr_[std::size_t(j - c0_)] + counts[std::size_t(j)];
  row_.resize(std::size_t(ptr_.back()));
  val_.resize(std::size_t(ptr_.back()));
  cursor_.assign(ptr_.begin(), ptr_.end() - 1);
  // Column i of `upper` holds row i of the lower triangle: its entries in the run's columns, below row `hi`.
  const int* Ap = upper.outerIndexPtr();
  auto row = [&](int i, int hi) {
    const int* e = Ai + Ap[i + 1];
    for (const int* p = std::lower_bound(Ai + Ap[i], e, c0_); p != e && *p < hi; ++p) {
      const std::size_t q = std::size_t(cursor_[std::size_t(*p - c0_)]++);
      row_[q] = i;
      val_[q] = Ax[p - Ai];
    }
  };
  for (int i = c0_; i < c1; ++i) row(i, i + 1);  // the run's own rows, then those below it that its fronts hold
  for (int i : outside_) row(i, c1);
}

std::vector<int> MatrixChunk::lower_counts(const SpMat& upper) {
  // Column ranges on the worker threads count the rows inside their own range in place and list those before it,
  // added once every range is done: in a nested-dissection order few rows lie before their column's range (a
  // serial pass over the matrix is init time that does not shrink with cores). Integer counts: the same on any
  // threads.
  std::vector<int> counts(std::size_t(upper.cols()), 0);
  const int* Ap = upper.outerIndexPtr();
  const int* Ai = upper.innerIndexPtr();
  std::vector<std::vector<int>> earlier;
  std::mutex adding;
  run_ranges(int(upper.cols()), 4096, [&](int lo, int hi) {
    std::vector<int> before;
    for (int i = lo; i < hi; ++i)
      for (int p = Ap[i]; p < Ap[i + 1] && Ai[p] <= i; ++p)
        if (Ai[p] >= lo)
          ++counts[std::size_t(Ai[p])];
        else
          before.push_back(Ai[p]);
    const std::lock_guard<std::mutex> lock(adding);
    earlier.push_back(std::move(before));
  });
  for (const std::vector<int>& rows : earlier)
    for (int r : rows) ++counts[std::size_t(r)];
  return counts;
}

}  // namespace db::multifrontal
