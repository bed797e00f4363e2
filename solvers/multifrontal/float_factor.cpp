#include "solvers/multifrontal/float_factor.h"

#include <algorithm>
#include <new>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/multifrontal/storage.h"

namespace db::multifrontal {

FloatFactor::FloatFactor(const FactorView& F) : entries_(F.S.xptr.back()) {
  values_.reset(new (std::nothrow) float[std::max<std::size_t>(entries_, 1)]);
  if (!values_)
    throw BudgetError(fmt::format("multifrontal_mixed: cannot allocate {} MB for the single-precision factor",
                                  bytes() >> 20));
  std::vector<double> buf;
  for (int s = 0; s < F.S.nsuper(); ++s) {
    const std::size_t a = F.S.xptr[std::size_t(s)], count = F.S.xptr[std::size_t(s) + 1] - a;
    const double* src = F.values.get() + a;
    if (F.values.on_file()) {  // read back, not faulted into the mapping (Mapping::read)
      buf.resize(count);
      F.values.read(src, count, buf.data());
      src = buf.data();
    }
    std::transform(src, src + count, values_.get() + a, [](double v) { return static_cast<float>(v); });
  }
}

void FloatFactor::solve(const Symbolic& S, const Plan& plan, RowMajorMat& y, std::vector<RowMajorMat>& acc) const {
  forward_all(view(S), plan, y, acc);
  backward_all(view(S), plan, y);
}

}  // namespace db::multifrontal
