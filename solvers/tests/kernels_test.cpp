// The solves' panel kernels on ranges (kernels.h), as the top supernodes' team runs them: a panel's rectangle in
// tiles of rows (forward) or columns (backward), around its triangle, must give every entry of x exactly what the
// whole kernel gives, for double and float factors, any number of right-hand sides, and tiles of any width (7 rows,
// 5 and 3 columns here: off the vector width, the last one ragged).
#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/multifrontal/kernels.h"
#include "solvers/multifrontal/storage.h"

namespace {

using namespace db::multifrontal;

template <class E>
struct PanelData {
  std::vector<E> tri, rect;
  std::vector<double> x;  //!< r columns of w + h entries (leading dimension w + h + 3)
  int w, h, r, ldx;
  PanelData(int w_, int h_, int r_, std::mt19937& rng) : w(w_), h(h_), r(r_), ldx(w_ + h_ + 3) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    tri.resize(std::size_t(w) * (w + 1) / 2);
    for (int j = 0; j < w; ++j)
      for (int i = j; i < w; ++i)
        tri[packed_column(j, w) + std::size_t(i - j)] = E(i == j ? 2.0 + u(rng) : 0.1 * u(rng));
    rect.resize(std::size_t(w) * h);
    for (auto& v : rect) v = E(u(rng));
    x.resize(std::size_t(ldx) * r);
    for (auto& v : x) v = u(rng);
  }
};

//! Tiles of `width` over n, the last one ragged, run in reverse (their order must not matter).
template <class Fn>
void tiles(int n, int width, const Fn& fn) {
  for (int k = (n + width - 1) / width - 1; k >= 0; --k) fn(k * width, std::min(n, (k + 1) * width));
}

template <class E>
void check_forward_and_backward(std::mt19937& rng) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{256, 700}, {37, 259}, {5, 3}})
    for (int r : {1, 2, 3, 5}) {
      SCOPED_TRACE(::testing::Message() << "w " << w << " h " << h << " r " << r << " float " << (sizeof(E) == 4));
      PanelData<E> a(w, h, r, rng);
      std::vector<double> whole = a.x, tiled = a.x;
      forward_panel(a.tri.data(), a.rect.data(), w, h, r, whole.data(), a.ldx);
      forward_panel(a.tri.data(), a.rect.data(), w, 0, r, tiled.data(), a.ldx);  // the triangle alone
      tiles(h, 7, [&](int i0, int i1) { forward_rect(a.rect.data(), w, h, i0, i1, r, tiled.data(), a.ldx); });
      EXPECT_TRUE(tiled == whole) << "forward";
      whole = tiled = a.x;
      backward_panel(a.tri.data(), a.rect.data(), w, h, r, whole.data(), a.ldx);
      tiles(w, 5, [&](int j0, int j1) { backward_rect(a.rect.data(), w, h, j0, j1, r, tiled.data(), a.ldx); });
      backward_panel(a.tri.data(), a.rect.data(), w, 0, r, tiled.data(), a.ldx);
      EXPECT_TRUE(tiled == whole) << "backward";
      if (r >= 2 && r <= 4) {  // backward_rows4's layout: row k of x in lanes 0..3 of x + 4k
        std::vector<double> rows(4 * std::size_t(w + h), 0.0);
        for (int k = 0; k < w + h; ++k)
          for (int c = 0; c < r; ++c) rows[4 * std::size_t(k) + std::size_t(c)] = a.x[std::size_t(c) * a.ldx + k];
        std::vector<double> whole4 = rows, tiled4 = rows;
        backward_rows4(a.tri.data(), a.rect.data(), w, h, whole4.data());
        tiles(w, 3, [&](int j0, int j1) { backward_rows4_rect(a.rect.data(), w, h, j0, j1, tiled4.data()); });
        backward_rows4(a.tri.data(), a.rect.data(), w, 0, tiled4.data());
        EXPECT_TRUE(tiled4 == whole4) << "backward, rows of four";
      }
    }
}

TEST(PanelKernels, RectangleTilesGiveTheWholeKernelsResults) {
  std::mt19937 rng(41);
  check_forward_and_backward<double>(rng);
  check_forward_and_backward<float>(rng);
}

}  // namespace
