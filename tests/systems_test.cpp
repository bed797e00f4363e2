// The quadratic-energy engine (systems/min_quad_with_fixed.h) against the exact solution, its per-frame fast path,
// the backend policy of the builds, and LRI's edge systems built both ways.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "solvers/base/error.h"
#include "edit/transform.h"
#include "exact_deformation.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "operators/frames.h"
#include "operators/lri_rows.h"
#include "systems/lri_system.h"
#include "systems/min_quad_with_fixed.h"
#include "systems/normal_system.h"
#include "solvers/tests/worker_threads.h"
#include "test_util.h"

namespace db {
namespace {

// A built LAP or TF system of the small tube, with its unknowns.
struct Built {
  Unknowns unk;
  NormalSystem sys;
};

Built build(EnergyKind kind, ConstraintMode mode, Build b) {
  const Mesh m = make_cylinder(6, 8, 1.0, 2.0);
  const Adjacency adj = vertex_adjacency(m);
  const Points Vn = Normalization::fit(m.V).apply(m.V);
  const EnergyOperator op(Vn, m.F, adj, kind, {});
  Built r;
  r.unk = make_unknowns(classify(tube_edit(m), mode), 2.0);
  r.sys = build_normal_system(op, r.unk, b);
  return r;
}

// The exact x_u (exact_reference.h): K x_u = g0 - C x_h + W u, with K and C from the sparse build.
DenseMat reference(const NormalSystem& s, const Unknowns& unk, const DenseMat& xh, const DenseMat& soft) {
  DenseMat rhs = s.g0 - DenseMat(s.C) * xh;
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (std::size_t k = 0; k < unk.soft_vertices.size(); ++k)
    rhs.middleRows(s.block * unk.unknown_of[unk.soft_vertices[k]], s.block) +=
        w2 * soft.middleRows(static_cast<Eigen::Index>(s.block * k), s.block);
  return exact::exact_solution(s.K, rhs, s.block);
}

DenseMat random_values(int rows, int cols, unsigned seed) {
  std::srand(seed);
  return DenseMat::Random(rows, cols);
}

TEST(MinQuadWithFixed, SolvesAsTheDenseReferenceForEveryBuild) {
  for (EnergyKind kind : {EnergyKind::Lap, EnergyKind::Tf})
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      const Built ref = build(kind, mode, Build::Structured);
      const int b = ref.sys.block, cols = ref.sys.rhs_cols;
      const DenseMat xh = random_values(b * ref.unk.num_hard(), cols, 1);
      const DenseMat soft = random_values(b * static_cast<int>(ref.unk.soft_vertices.size()), cols, 2);
      const DenseMat want = reference(ref.sys, ref.unk, xh, soft);
      const double tol = exact::solve_bound(exact::condition_number(ref.sys.K));  // the builds' K differ by rounding
      for (Build bd : {Build::Dense, Build::Naive, Build::Structured}) {
        const std::string what = to_string(kind) + "/" + to_string(mode) + "/" + to_string(bd);
        Built got = build(kind, mode, bd);
        MinQuadWithFixed q;
        q.precompute(std::move(got.sys), got.unk, "test", "", SolverOptions{}, true);
        EXPECT_EQ(q.report().n, static_cast<std::size_t>(want.rows())) << what;
        EXPECT_EQ(q.report().backend, bd == Build::Dense ? "dense_llt" : "multifrontal") << what;
        EXPECT_GT(q.report().factor.nnz_factor, 0u) << what;
        q.form_rhs(xh, soft);
        DenseMat x;
        q.solve(x);
        EXPECT_WITHIN(exact::rel(x, want), tol) << what;
        EXPECT_EQ(q.system().K.nonZeros(), 0) << what;  // consumed
        EXPECT_EQ(q.system().K_dense.size(), 0) << what;
      }
    }
}

TEST(MinQuadWithFixed, FastPathAndGivenLinearTermAgreeWithAFullSolve) {
  Built a = build(EnergyKind::Tf, ConstraintMode::Hard, Build::Structured);
  const SpMat K = a.sys.K;
  const int b = a.sys.block;
  const DenseMat soft(0, 1), xh0 = random_values(b * a.unk.num_hard(), 1, 3);
  MinQuadWithFixed q;
  q.precompute(NormalSystem(a.sys), a.unk, "tf", "multifrontal", SolverOptions{}, false);
  EXPECT_EQ(q.system().K.nonZeros(), K.nonZeros());  // kept
  // The first half of the hard values move, the rest stay at their base values.
  std::vector<int> moving;
  for (int h = 0; h < a.unk.num_hard() / 2; ++h) moving.push_back(h);
  q.set_varying(moving, {});
  ASSERT_TRUE(q.base_pending());
  q.set_base(xh0, soft);
  EXPECT_FALSE(q.base_pending());
  DenseMat xh = xh0;
  xh.topRows(b * static_cast<Eigen::Index>(moving.size())) += random_values(b * static_cast<int>(moving.size()), 1, 4);
  DenseMat fast, full;
  q.form_rhs(xh, soft);
  q.solve(fast);
  const DenseMat want = reference(a.sys, a.unk, xh, soft);
  const double tol = exact::solve_bound(exact::condition_number(K));
  EXPECT_WITHIN(exact::rel(fast, want), tol);
  // A linear term given for the frame replaces g0.
  MinQuadWithFixed plain;
  plain.precompute(NormalSystem(a.sys), a.unk, "tf", "cholmod_supernodal", SolverOptions{}, true);
  plain.form_rhs(xh, soft, [&](DenseMat& g) { g += a.sys.g0; });
  plain.solve(full);
  EXPECT_WITHIN(exact::rel(full, want), tol);
}

TEST(MinQuadWithFixed, BackendPolicyOfTheBuilds) {
  EXPECT_EQ(resolve_solver("", Build::Structured), "multifrontal");
  EXPECT_EQ(resolve_solver("", Build::Naive), "multifrontal");
  EXPECT_EQ(resolve_solver("", Build::Dense), "dense_llt");
  for (const std::string& name : solver_names()) {
    const bool dense = solver_info(name).family == "dense";
    EXPECT_EQ(resolve_solver(name, Build::Structured), name);  // dense backends expand a sparse K
    if (dense) {
      EXPECT_EQ(resolve_solver(name, Build::Dense), name);
    } else {
      expect_input_error([&] { resolve_solver(name, Build::Dense); }, "'" + name + "'");
      expect_input_error([&] { resolve_solver(name, Build::Dense); }, "dense build");
    }
  }
  EXPECT_THROW(resolve_solver("no_such_solver", Build::Structured), Error);
}

// Every dense backend against the exact deformation (exact_deformation.h), under the bound of the system's
// conditioning: the backends round differently, so they are not compared with each other.
TEST(MinQuadWithFixed, DenseBuildHonoursTheSolver) {
  const Mesh m = make_cylinder(8, 10, 1.0, 3.0);
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(0, 1, 0), 40.0, Vec3(0, 0, 3));
  for (const char* method : {"lap", "tf"}) {
    DeformOptions o;
    o.method = parse_enum<Method>(method);
    const Points ref = make_deformer(m, e, exact_options(o))->deform(T);
    const double tol = exact::solve_bound(system_condition(m, e, o));
    o.build = Build::Dense;
    auto d = make_deformer(m, e, o);
    EXPECT_WITHIN(normalized_rel(m, d->deform(T), ref), tol) << method << " dense_llt";
    EXPECT_EQ(d->systems().front().factor.ordering_used, "none");
    for (const char* solver : {"lapack_potrf", "dense_ldlt_bk", "dense_lu"}) {
      o.solver = solver;
      auto other = make_deformer(m, e, o);
      EXPECT_WITHIN(normalized_rel(m, other->deform(T), ref), tol) << method << " " << solver;
      EXPECT_GT(other->factor_bytes(), 0u) << solver;
    }
    o.solver = "multifrontal";
    EXPECT_THROW(make_deformer(m, e, o), UsageError);  // options that do not go together (resolve_options)
    o.build = Build::Structured;
    o.solver = "dense_llt";  // a dense backend on a sparse build: allowed
    EXPECT_WITHIN(normalized_rel(m, make_deformer(m, e, o)->deform(T), ref), tol) << method;
  }
}

// Frame and position systems of LRI, naive against structured, and their right-hand sides' linear term A_u^T t
// against the naive build's explicit A_u.
TEST(StructuredBuild, PredictedBytesAndOperatorTheSameOnAnyThreads) {
  // 15000 vertices: several vertex ranges (4096 each at least) for the Laplacian coordinates and the stencil counts.
  const Mesh m = make_cylinder(150, 100, 1.0, 2.0);
  const Adjacency adj = vertex_adjacency(m);
  const Points Vn = Normalization::fit(m.V).apply(m.V);
  const Unknowns unk = make_unknowns(classify(tube_edit(m), ConstraintMode::Soft), 2.0);
  Points delta_1;
  for (int threads : {1, 4}) {
    test::WorkerThreads env(threads);
    const EnergyOperator op(Vn, m.F, adj, EnergyKind::Tf, {});
    if (threads == 1) delta_1 = op.delta();
    EXPECT_EQ(op.delta(), delta_1) << threads << " threads";
    const NormalSystem sys = build_normal_system(op, unk, Build::Structured);
    const std::size_t entry = sizeof(double) + sizeof(int);
    EXPECT_EQ(predict_build_bytes(op, unk, Build::Structured),
              std::size_t(sys.K.nonZeros()) * entry + std::size_t(sys.C.nonZeros()) * entry +
                  std::size_t(sys.g0.size()) * sizeof(double))
        << threads << " threads";
  }
}

TEST(LriSystems, StructuredEqualsNaive) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const FrameField frames = compute_frames(m.V, adj, N, FrameStrategy::HeightAngle);
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    const Unknowns unk = make_unknowns(classify(tube_edit(m), mode), 2.0);
    for (const EdgeRows& rows : {lri_frame_rows(frames.F), lri_position_rows()}) {
      const std::string what = to_string(mode) + " block " + std::to_string(rows.block);
      const NormalSystem s = build_edge_system(adj, unk, rows, Build::Structured);
      const NormalSystem n = build_edge_system(adj, unk, rows, Build::Naive);
      EXPECT_EQ(s.block, rows.block);
      EXPECT_EQ(s.g0.size(), 0) << what;
      EXPECT_EQ(s.n(), static_cast<std::size_t>(rows.block * unk.num_unknowns())) << what;
      EXPECT_LT((DenseMat(s.K) - DenseMat(n.K)).norm(), 1e-12 * DenseMat(n.K).norm()) << what;
      EXPECT_LT((DenseMat(s.C) - DenseMat(n.C)).norm(), 1e-12 * std::max(1.0, DenseMat(n.C).norm())) << what;
      EXPECT_LT(s.total_held_bytes(), n.total_held_bytes()) << what;
    }
    EXPECT_THROW(build_edge_system(adj, unk, lri_position_rows(), Build::Dense), InputError);
    EXPECT_THROW(build_edge_system(adj, unk, lri_position_rows(), Build::Structured, 100), BudgetError);
  }
}

TEST(LriSystems, AtTargetsIsTheTransposedOperatorTimesTheTargets) {
  // With every vertex unknown (no hard ones), A_u is the whole edge operator: rows x_j - x_i per directed edge.
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Unknowns unk = make_unknowns(std::vector<Constraint>(m.num_vertices(), Constraint::Soft), 1.0);
  const DenseMat t = random_values(static_cast<int>(adj.nbr.size()), 3, 5);
  DenseMat g = DenseMat::Zero(unk.num_unknowns(), 3);
  add_At_targets(adj, unk, lri_position_rows(), t, g);
  DenseMat want = DenseMat::Zero(unk.num_unknowns(), 3);
  for (int i = 0; i < adj.num_vertices(); ++i)
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
      want.row(unk.unknown_of[i]) -= t.row(s);
      want.row(unk.unknown_of[adj.nbr[s]]) += t.row(s);
    }
  EXPECT_LT((g - want).norm(), 1e-12 * want.norm());
}

}  // namespace
}  // namespace db
