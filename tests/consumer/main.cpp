// A consumer of the installed libraries: solves a system with deformbench::solvers, then deforms a generated bar
// with deformbench::deform and writes it. Checks answers that are exact, so it holds on any machine:
//  - the 1-D Poisson system tridiag(-1, 2, -1) x = 1 has x_i = i (n + 1 - i) / 2; a backward-stable solve lies
//    within 16 eps cond(A) of it, cond(A) = cot^2(pi / (2 (n + 1)));
//  - hard constraints are eliminated, so the handle lands on the transformed rest positions and the fixed vertices
//    stay where they were, up to the rounding of the normalization round trip (a few ulps of the bounding box).
// Usage: consumer OUT.off   (exit 0 on success, 1 with a message otherwise)
#include <cmath>
#include <cstdio>
#include <limits>

#include "edit/edit.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "solvers/linear_solver.h"

namespace {
bool fail(const char* what) {
  std::fprintf(stderr, "consumer: %s\n", what);
  return false;
}

bool poisson_solve_is_exact() {
  const int n = 200;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);  // upper triangle, as the interface takes it
  }
  db::SpMat upper(n, n);
  upper.setFromTriplets(t.begin(), t.end());
  auto solver = db::make_solver("multifrontal");
  solver->analyze(upper);
  solver->factorize(upper);
  db::DenseMat b = db::DenseMat::Ones(n, 1), x;
  solver->solve(b, x);
  const double pi = std::acos(-1.0), c = 1.0 / std::tan(pi / (2.0 * (n + 1)));
  const double bound = 16 * std::numeric_limits<double>::epsilon() * c * c;
  double err = 0, norm = 0;
  for (int i = 1; i <= n; ++i) {
    const double exact = 0.5 * i * (n + 1 - i);
    err = std::max(err, std::abs(x(i - 1) - exact));
    norm = std::max(norm, exact);
  }
  return err <= bound * norm || fail("multifrontal: the Poisson solution is off by more than 16 eps cond");
}

bool bar_deforms(const char* out) {
  const db::Mesh bar = db::make_bar(4, 4, 20, 1.0, 1.0, 5.0);
  db::Edit edit;
  edit.name = "lift";
  edit.roles.resize(bar.V.rows(), db::Role::Free);
  for (int v = 0; v < bar.V.rows(); ++v) {
    if (bar.V(v, 2) <= 0.5) edit.roles[v] = db::Role::Fixed;
    if (bar.V(v, 2) >= 4.5) edit.roles[v] = db::Role::Handle;
  }
  edit.transform(0, 3) = 1.0;  // the top moves one unit along x
  db::validate_edit(bar, edit);
  db::Mesh deformed = bar;
  deformed.V = db::make_deformer(bar, edit, db::DeformOptions{})->deform(edit.transform);
  const double ulps = 8 * std::numeric_limits<double>::epsilon() * 6.0;  // the bar's box diagonal is below 6
  for (int v = 0; v < bar.V.rows(); ++v) {
    const db::Vec3 rest = bar.V.row(v).transpose(), now = deformed.V.row(v).transpose();
    if (edit.roles[v] == db::Role::Fixed && (now - rest).norm() > ulps) return fail("a fixed vertex moved");
    if (edit.roles[v] == db::Role::Handle && (now - db::apply(edit.transform, rest)).norm() > ulps)
      return fail("a handle vertex is not where the transform puts it");
    if (!now.allFinite()) return fail("a free vertex is not finite");
  }
  db::write_mesh(out, deformed);
  return db::read_mesh(out).V.rows() == bar.V.rows() || fail("the written mesh has another vertex count");
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return fail("usage: consumer OUT.off"), 1;
  try {
    return poisson_solve_is_exact() && bar_deforms(argv[1]) ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
