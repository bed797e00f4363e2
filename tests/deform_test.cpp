// Invariants of the LAP and TF deformations and of the three system builds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "solvers/base/error.h"
#include "edit/edit_io.h"
#include "exact_deformation.h"
#include "edit/transform.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/linear_solver.h"
#include "systems/normal_system.h"
#include "solvers/tests/worker_threads.h"
#include "systems/vertex_ordering.h"
#include "test_util.h"

namespace db {
namespace {

DeformOptions opts(const std::string& method, ConstraintMode mode = ConstraintMode::Hard, double w = 1.0) {
  DeformOptions o;
  o.method = parse_enum<Method>(method);
  o.constraints = mode;
  o.soft_weight = w;
  return o;
}

class ByMethod : public ::testing::TestWithParam<std::string> {};

TEST_P(ByMethod, IdentityEditReproducesTheMesh) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    for (Weights w : {Weights::Uniform, Weights::Cotan}) {
      for (bool translation : {true, false}) {
        DeformOptions o = opts(GetParam(), mode);
        o.weights = w;
        o.tf_translation = translation;
        const Points out = make_deformer(m, e, o)->deform(Mat4::Identity());
        EXPECT_LT((out - m.V).norm() / m.V.norm(), 1e-9)
            << to_string(mode) << " " << to_string(w) << " translation=" << translation;
      }
    }
  }
}

TEST_P(ByMethod, RigidTranslationOfAllConstraintsTranslatesTheMesh) {
  const Mesh m = tube();
  const Edit e = tube_edit(m, /*all_handle=*/true);
  const Mat4 T = translation(Vec3(0.3, -1.2, 2.5));
  auto d = make_deformer(m, e, opts(GetParam()));
  EXPECT_LT(rel_rms(d->deform(T), transformed(m.V, T)), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Methods, ByMethod, ::testing::Values("lap", "tf"));

TEST(Deform, RigidRotationTfFollowsLapDoesNot) {
  // Handle and fixed parts rotated rigidly: the ideal result is the rotated mesh. TF's per-vertex similarity
  // s I + [h]x is a linearized rotation, so it follows moderate rotations closely and degrades towards 90
  // degrees (there a rotation about x is fitted as a y-z rotation that also scales x by cos(angle)); LAP does
  // not rotate its coordinates at all. Both errors are printed for the record.
  const Mesh m = tube();
  const Edit e = tube_edit(m, /*all_handle=*/true);
  for (double degrees : {30.0, 90.0}) {
    const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), degrees, Vec3(0, 0, 2));
    const Points ideal = transformed(m.V, T);
    const double err_lap = rel_rms(make_deformer(m, e, opts("lap"))->deform(T), ideal);
    const double err_tf = rel_rms(make_deformer(m, e, opts("tf"))->deform(T), ideal);
    RecordProperty("rel_rms_lap_" + std::to_string(int(degrees)), std::to_string(err_lap));
    RecordProperty("rel_rms_tf_" + std::to_string(int(degrees)), std::to_string(err_tf));
    std::printf("%.0f degree rigid rotation, RMS distance to the rotated mesh / bbox diagonal: lap %.4f, tf %.4f\n",
                degrees, err_lap, err_tf);
    EXPECT_LT(err_tf, err_lap) << degrees;
    if (degrees <= 30) {
      EXPECT_LT(err_tf, 0.5 * err_lap);
      EXPECT_LT(err_tf, 0.005);
    }
  }
}

// The three builds assemble the same normal matrix (structured == explicitly formed A^T A == dense).
TEST(Systems, StructuredEqualsExplicitNormalMatrix) {
  const Mesh m = make_cylinder(6, 8, 1.0, 2.0);
  const Adjacency adj = vertex_adjacency(m);
  const Edit e = tube_edit(m);
  const Points Vn = Normalization::fit(m.V).apply(m.V);
  for (EnergyKind kind : {EnergyKind::Lap, EnergyKind::Tf}) {
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      const EnergyOperator op(Vn, m.F, adj, kind, {});
      const Unknowns unk = make_unknowns(classify(e, mode), 3.0);
      const NormalSystem s = build_normal_system(op, unk, Build::Structured);
      const NormalSystem nv = build_normal_system(op, unk, Build::Naive);
      const NormalSystem dn = build_normal_system(op, unk, Build::Dense);
      const DenseMat Ks = DenseMat(s.K).selfadjointView<Eigen::Upper>();
      const DenseMat Kn = DenseMat(nv.K).selfadjointView<Eigen::Upper>();
      const double scale = dn.K_dense.norm();
      const std::string what = to_string(kind) + "/" + to_string(mode);
      EXPECT_LT((Ks - Kn).norm() / scale, 1e-12) << what;
      EXPECT_LT((Ks - dn.K_dense).norm() / scale, 1e-12) << what;
      EXPECT_LT((DenseMat(s.C) - DenseMat(nv.C)).norm() / scale, 1e-12) << what;
      EXPECT_LT((DenseMat(s.C) - dn.C_dense).norm() / scale, 1e-12) << what;
      EXPECT_LT((s.g0 - nv.g0).norm() / std::max(1.0, nv.g0.norm()), 1e-12) << what;
      // The structured build stores strictly less than the naive one.
      EXPECT_LT(s.total_held_bytes(), nv.total_held_bytes()) << what;
      // The naive build keeps A^T, A_h and b for its frames (the thesis' first version): its per-frame
      // right-hand side A^T (b - A_h x_h) is g0 - C x_h, for any handle positions.
      ASSERT_EQ(nv.At.rows(), nv.g0.rows()) << what;
      EXPECT_EQ(s.At.size(), 0) << what;
      const DenseMat xh = DenseMat::Random(nv.C.cols(), nv.g0.cols());
      const DenseMat per_frame = nv.At * DenseMat(nv.targets - nv.Ah * xh);
      const DenseMat from_g0 = nv.g0 - nv.C * xh;
      EXPECT_LT((per_frame - from_g0).norm() / std::max(1.0, from_g0.norm()), 1e-12) << what;
    }
  }
}

// METIS orderings of large graphs are dissected and their parts ordered on threads (solvers/graph_ordering.cpp):
// each must be a permutation, the same on every run for a thread count, the same for one and two threads (one
// level), and as good as METIS run whole; more threads dissect one more level per doubling, at some fill. At 16
// threads the parts above the levels' mean are split again and the parts are claimed by size: still the same on
// every run.
TEST(Systems, MetisVertexOrderingIsDeterministicPerThreadCountAndKeepsTheFill) {
  const Mesh m = make_cylinder(150, 160, 1.0, 8.0);  // 24000 vertices: above the dissection threshold
  const Adjacency adj = vertex_adjacency(m);
  std::vector<Constraint> kinds(static_cast<std::size_t>(m.V.rows()), Constraint::Free);
  for (int v = 0; v < 160; ++v) kinds[static_cast<std::size_t>(v)] = Constraint::Hard;
  const Unknowns original = make_unknowns(kinds, 1.0);
  auto factor_entries = [&](const Unknowns& unk, const std::string& ordering) {
    SolverOptions o;
    o.ordering = ordering;
    auto solver = make_solver("cholmod_supernodal", o);
    solver->analyze(expand_upper(interaction_pattern(adj, unk), 1));
    return static_cast<double>(solver->stats().nnz_factor);
  };
  const std::vector<const char*> threads = {"1", "2", "2", "4", "4", "16", "16"};
  std::vector<Unknowns> ordered;
  for (const char* t : threads) {
    const db::test::WorkerThreads scope(std::atoi(t));
    ordered.push_back(original);
    order_unknowns(adj, ordered.back(), "metis");
  }
  EXPECT_EQ(ordered[0].unknown_vertices, ordered[1].unknown_vertices);
  EXPECT_EQ(ordered[1].unknown_vertices, ordered[2].unknown_vertices);
  EXPECT_EQ(ordered[3].unknown_vertices, ordered[4].unknown_vertices);
  EXPECT_EQ(ordered[5].unknown_vertices, ordered[6].unknown_vertices);
  const double whole = factor_entries(original, "metis"), amd = factor_entries(original, "amd");
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    const Unknowns& unk = ordered[k];
    std::vector<int> sorted = unk.unknown_vertices;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, original.unknown_vertices) << threads[k] << " threads";
    for (int u = 0; u < unk.num_unknowns(); ++u) EXPECT_EQ(unk.unknown_of[unk.unknown_vertices[u]], u);
    const double dissected = factor_entries(unk, "natural");
    EXPECT_LT(dissected, 1.1 * whole) << threads[k] << " threads: whole METIS " << whole << ", dissected " << dissected;
    EXPECT_LT(dissected, amd) << threads[k] << " threads";
  }
}

// Building while the ordering runs, then renumbering (the LAP default with two threads), must give the
// system that ordering first and building in that numbering gives: the same unknowns' order, the same K (upper,
// rows ascending in every column), C and g0; for 3x3 blocks too, and with hard and soft constraints.
TEST(Systems, BuildWhileOrderingEqualsOrderThenBuild) {
  const Mesh m = make_cylinder(30, 24, 1.0, 4.0);
  const Adjacency adj = vertex_adjacency(m);
  const Edit e = tube_edit(m);
  const Points Vn = Normalization::fit(m.V).apply(m.V);
  for (EnergyKind kind : {EnergyKind::Lap, EnergyKind::Tf}) {
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      const std::string what = to_string(kind) + "/" + to_string(mode);
      const EnergyOperator op(Vn, m.F, adj, kind, {});
      Unknowns first = make_unknowns(classify(e, mode), 2.0), meanwhile = first;
      order_unknowns(adj, first, "amd");
      const NormalSystem ref = build_normal_system(op, first, Build::Structured);
      double ordering_seconds = -1;
      const NormalSystem got = build_structured_while_ordering(op, meanwhile, "amd", 0, ordering_seconds);
      EXPECT_GE(ordering_seconds, 0) << what;
      EXPECT_EQ(meanwhile.unknown_vertices, first.unknown_vertices) << what;
      EXPECT_EQ(meanwhile.unknown_of, first.unknown_of) << what;
      ASSERT_EQ(got.K.nonZeros(), ref.K.nonZeros()) << what;
      for (int j = 0; j < got.K.outerSize(); ++j)
        for (int k = got.K.outerIndexPtr()[j]; k + 1 < got.K.outerIndexPtr()[j + 1]; ++k)
          ASSERT_LT(got.K.innerIndexPtr()[k], got.K.innerIndexPtr()[k + 1]) << what << " column " << j;
      EXPECT_LT((DenseMat(got.K) - DenseMat(ref.K)).norm(), 1e-12 * DenseMat(ref.K).norm()) << what;
      EXPECT_LT((DenseMat(got.C) - DenseMat(ref.C)).norm(), 1e-12 * std::max(1.0, DenseMat(ref.C).norm())) << what;
      EXPECT_LT((got.g0 - ref.g0).norm(), 1e-12 * std::max(1.0, ref.g0.norm())) << what;
      EXPECT_EQ(got.block, ref.block);
    }
  }
}

// Rank-local assembly (mpirun, --solver mumps): each rank builds the share of the structured system its unknowns
// own, and MUMPS sums the ranks' entries; so the shares of K, C and g0 must sum to the one-process system (exactly:
// each entry is accumulated by one share, in the same order), no share may hold another's columns or rows, and
// every soft weight must be counted once. LAP and TF, hard and soft constraints, 1 to 3 parts, in a METIS order.
TEST(Systems, RankSharesSumToTheWholeSystem) {
  const Mesh m = make_cylinder(20, 16, 1.0, 4.0);
  const Adjacency adj = vertex_adjacency(m);
  const Edit e = tube_edit(m);
  const Points Vn = Normalization::fit(m.V).apply(m.V);
  for (EnergyKind kind : {EnergyKind::Lap, EnergyKind::Tf})
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      const EnergyOperator op(Vn, m.F, adj, kind, {});
      Unknowns unk = make_unknowns(classify(e, mode), 2.0);
      order_unknowns(adj, unk, "metis");
      const NormalSystem whole = build_normal_system(op, unk, Build::Structured);
      const DenseMat K = DenseMat(whole.K), C = DenseMat(whole.C);
      ASSERT_GT(K.norm(), 0);
      for (int parts = 1; parts <= 3; ++parts) {
        const std::string what = to_string(kind) + "/" + to_string(mode) + "/" + std::to_string(parts) + " parts";
        DenseMat Ks = DenseMat::Zero(K.rows(), K.cols()), Cs = DenseMat::Zero(C.rows(), C.cols());
        DenseMat g = DenseMat::Zero(whole.g0.rows(), whole.g0.cols());
        Eigen::Index stored = 0;
        for (int part = 0; part < parts; ++part) {
          const NormalSystem s = build_structured_share(op, unk, part, parts);
          const auto [first, last] = share_range(unk.num_unknowns(), part, parts);
          EXPECT_EQ(s.parts, parts) << what;
          EXPECT_EQ(s.own_begin, first) << what;
          EXPECT_EQ(s.own_end, last) << what;
          ASSERT_EQ(s.K.rows(), K.rows()) << what;
          const Eigen::Index lo = s.block * first, hi = s.block * last;
          // Nothing outside the share: K's other columns, C's and g0's other rows are empty.
          EXPECT_EQ(s.K.outerIndexPtr()[lo], 0) << what;
          EXPECT_EQ(s.K.outerIndexPtr()[s.K.cols()], s.K.outerIndexPtr()[hi]) << what;
          const DenseMat Cp = DenseMat(s.C);
          EXPECT_EQ(Cp.topRows(lo).norm() + Cp.bottomRows(Cp.rows() - hi).norm(), 0) << what;
          EXPECT_EQ(s.g0.topRows(lo).norm() + s.g0.bottomRows(s.g0.rows() - hi).norm(), 0) << what;
          Ks += DenseMat(s.K);
          Cs += Cp;
          g += s.g0;
          stored += s.K.nonZeros();
        }
        EXPECT_EQ(stored, whole.K.nonZeros()) << what;
        // lpNorm<Infinity>: 0 for C without columns (soft constraints leave no hard vertex).
        EXPECT_EQ((Ks - K).lpNorm<Eigen::Infinity>(), 0) << what;
        EXPECT_EQ((Cs - C).lpNorm<Eigen::Infinity>(), 0) << what;
        EXPECT_EQ((g - whole.g0).lpNorm<Eigen::Infinity>(), 0) << what;
      }
    }
}

// Each build against the exact deformation (exact_deformation.h), under the bound of the system's conditioning:
// the builds sum K's entries in different orders, so their solves round differently.
TEST(Systems, BuildsGiveTheSameDeformation) {
  const Mesh m = make_cylinder(8, 10, 1.0, 3.0);
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(0, 1, 0), 40.0, Vec3(0, 0, 3));
  for (const char* method : {"lap", "tf"})
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      DeformOptions o = opts(method, mode);
      const Points ref = make_deformer(m, e, exact_options(o))->deform(T);
      const double tol = exact::solve_bound(system_condition(m, e, o));
      for (Build b : {Build::Dense, Build::Naive, Build::Structured}) {
        o.build = b;
        const Points out = make_deformer(m, e, o)->deform(T);
        EXPECT_WITHIN(normalized_rel(m, out, ref), tol) << method << " " << to_string(mode) << " " << to_string(b);
      }
    }
}

TEST(Deform, EveryBackendGivesTheSameDeformation) {
  // Through the whole pipeline (structured build, vertex ordering where the backend takes a given order), each
  // backend against the exact deformation under the bound the system's conditioning allows it: a direct solve's
  // (exact::solve_bound), an iterative one's relative residual (at most its tolerance) times cond.
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(0, 1, 0), 45.0, Vec3(0, 0, 4));
  for (const char* method : {"lap", "tf"}) {
    const Points ref = make_deformer(m, e, exact_options(opts(method)))->deform(T);
    const double cond = system_condition(m, e, opts(method));
    for (const std::string& solver : solver_names()) {
      DeformOptions o = opts(method);
      o.solver = solver;
      const Points out = make_deformer(m, e, o)->deform(T);
      const double tol = solver_info(solver).family == "iterative"
                             ? exact::kSolveFactor * cond * o.solver_options.tolerance
                             : exact::solve_bound(cond);
      EXPECT_WITHIN(normalized_rel(m, out, ref), tol) << method << " " << solver;
    }
  }
}

TEST(Deform, SoftConstraintsConvergeToHardOnesAsTheWeightGrows) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), 30.0, Vec3(0, 0, 4)) * translation(Vec3(0, 0.5, 0));
  for (const char* method : {"lap", "tf"}) {
    const Points hard = make_deformer(m, e, opts(method))->deform(T);
    double prev = 1e300;
    for (double w : {1.0, 10.0, 100.0, 1000.0}) {
      const double err = rel_rms(make_deformer(m, e, opts(method, ConstraintMode::Soft, w))->deform(T), hard);
      EXPECT_LT(err, prev) << method << " w=" << w;
      prev = err;
    }
    EXPECT_LT(prev, 1e-4) << method;
  }
}

TEST(Deform, HardHandleVerticesReachTheirTargetsExactly) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(0, 1, 0), 60.0, Vec3(0, 0, 4));
  for (const char* method : {"lap", "tf"}) {
    const Points out = make_deformer(m, e, opts(method))->deform(T);
    for (int v = 0; v < m.num_vertices(); ++v) {
      const Vec3 want = e.roles[v] == Role::Handle ? apply(T, m.V.row(v).transpose()) : m.V.row(v).transpose();
      if (e.roles[v] != Role::Free) {
        EXPECT_LT((out.row(v).transpose() - want).norm(), 1e-9);
      }
    }
  }
}

TEST(Deform, ComponentWithoutConstraintIsReportedSingular) {
  // Two disjoint tubes; only the first carries constraints.
  const Mesh a = tube();
  Mesh m;
  m.V.resize(2 * a.num_vertices(), 3);
  m.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  m.F.resize(2 * a.num_faces(), 3);
  m.F << a.F, (a.F.array() + a.num_vertices()).matrix();
  Edit e = tube_edit(a);
  e.roles.resize(m.num_vertices(), Role::Free);
  try {
    make_deformer(m, e, opts("lap"));
    FAIL() << "expected InputError";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("singular"), std::string::npos) << err.what();
  }
}

// TF is blind to the linearized similarities (s I + [h]x) v + t: constrained vertices that all lie on one line (a
// single one, or the tube's seam) leave the tube free to rotate about it, so the system is singular; the
// structural check says so before any factorization (whose pivot test no longer decides for the deformers).
// Three pins off one line are enough, and LAP needs only one.
TEST(Deform, TfPinnedOnOneLineIsRejectedAsSingular) {
  const Mesh m = tube();
  std::vector<int> seam;  // vertices on the line y = 0, x > 0 (parallel to the axis)
  for (int v = 0; v < m.num_vertices(); ++v)
    if (std::abs(m.V(v, 1)) < 1e-12 && m.V(v, 0) > 0) seam.push_back(v);
  ASSERT_GE(seam.size(), 3u);
  auto pinned = [&](const std::vector<int>& vs) {
    Edit e;
    e.roles.assign(m.num_vertices(), Role::Free);
    for (int v : vs) e.roles[v] = Role::Handle;
    return e;
  };
  int off_line = -1;  // a vertex of the first seam vertex's ring, a quarter turn away
  for (int v = 0; v < m.num_vertices() && off_line < 0; ++v)
    if (std::abs(m.V(v, 2) - m.V(seam[0], 2)) < 1e-12 && std::abs(m.V(v, 0)) < 1e-9) off_line = v;
  ASSERT_GE(off_line, 0);
  for (ConstraintMode mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    SCOPED_TRACE(to_string(mode));
    for (const std::vector<int>& pins : {std::vector<int>{0}, seam}) {
      try {
        make_deformer(m, pinned(pins), opts("tf", mode));
        FAIL() << "expected InputError for " << pins.size() << " pin(s) on one line";
      } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("one line"), std::string::npos) << err.what();
      }
      EXPECT_TRUE(make_deformer(m, pinned(pins), opts("lap", mode))->deform(Mat4::Identity()).allFinite());
    }
    const Points out = make_deformer(m, pinned({seam[0], seam.back(), off_line}), opts("tf", mode))
                           ->deform(Mat4::Identity());
    EXPECT_LT(rel_rms(out, m.V), 1e-8);  // the identity edit keeps the mesh
  }
}

// The BS08 survey cases (data/bs08).
const std::filesystem::path kBs08 = bs08_dir();

class Bs08 : public ::testing::TestWithParam<std::string> {};

TEST_P(Bs08, LapAndTfRunAndHonourTheHandle) {
  const auto stem = kBs08 / GetParam();
  ASSERT_TRUE(std::filesystem::exists(stem.string() + ".off")) << stem << ".off is missing: the BS08 edits are bundled in data/bs08";
  const EditCase ec = load_edit_case(stem.string());
  for (const char* method : {"lap", "tf"}) {
    const Points out = make_deformer(ec.mesh, ec.edit, opts(method))->deform(ec.edit.transform);
    ASSERT_TRUE(out.allFinite()) << method;
    double worst = 0;
    for (int v : ec.edit.vertices(Role::Handle))
      worst = std::max(worst, (out.row(v).transpose() - apply(ec.edit.transform, ec.mesh.V.row(v).transpose())).norm());
    EXPECT_LT(worst / bbox_diagonal(ec.mesh.V), 1e-9) << method;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Bs08, ::testing::ValuesIn(kBs08Cases));

TEST(Bs08Cactus, TfFactorsOnceCoordinatesAreNormalized) {
  // Known case: in raw coordinates a straightforward TF normal matrix of this edit is reported indefinite by
  // CHOLMOD; centered and scaled it factors. Raw coordinates must fail loudly or succeed, never give NaN.
  const auto stem = kBs08 / "cactus";
  ASSERT_TRUE(std::filesystem::exists(stem.string() + ".off")) << stem << ".off is missing: the BS08 edits are bundled in data/bs08";
  const EditCase ec = load_edit_case(stem.string());
  DeformOptions o = opts("tf");
  EXPECT_TRUE(make_deformer(ec.mesh, ec.edit, o)->deform(ec.edit.transform).allFinite());
  o.normalize = false;
  try {
    const Points raw = make_deformer(ec.mesh, ec.edit, o)->deform(ec.edit.transform);
    EXPECT_TRUE(raw.allFinite());
  } catch (const SolverError& err) {
    EXPECT_NE(std::string(err.what()).find("positive definite"), std::string::npos) << err.what();
  }
}

}  // namespace
}  // namespace db
