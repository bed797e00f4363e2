// The mixed-precision backend (multifrontal_mixed) in the deformers: on the BS08 edits its TF and LAP results equal
// the exact solution (multifrontal_refined at a tighter tolerance) to the refinements' tolerances, and its solves
// report their iterations and residual.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "solvers/base/error.h"
#include "edit/edit_io.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "solvers/tests/exact_reference.h"
#include "test_util.h"

namespace db {
namespace {

DeformOptions opts(const std::string& method, const std::string& solver, ConstraintMode mode,
                   double tolerance = 1e-12) {
  DeformOptions o;
  o.method = parse_enum<Method>(method);
  o.solver = solver;
  o.constraints = mode;
  o.solver_options.tolerance = tolerance;
  return o;
}

class MixedBs08 : public ::testing::TestWithParam<std::string> {};

// The reference is the exact solution, not the plain double solve: on these ill-conditioned TF systems the double
// solve's own error is of the size of a fixed tolerance and depends on the BLAS kernels and the thread count.
// Refined solves lie within refined_bound() of the exact solution (exact_reference.h), measured in the deformers'
// normalized coordinates (methods/normalization.h), where the systems are solved.
TEST_P(MixedBs08, EqualsTheExactSolution) {
  const auto stem = bs08_dir() / GetParam();
  ASSERT_TRUE(std::filesystem::exists(stem.string() + ".off")) << stem << ".off is missing (data/bs08)";
  const EditCase ec = load_edit_case(stem.string());
  const Normalization unit = Normalization::fit(ec.mesh.V);
  const double tolerance = 1e-12;
  for (const char* method : {"tf", "lap"})
    for (ConstraintMode mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      SCOPED_TRACE(std::string(method) + " " + to_string(mode));
      const auto mixed = make_deformer(ec.mesh, ec.edit, opts(method, "multifrontal_mixed", mode, tolerance));
      const Points xm = unit.apply(mixed->deform(ec.edit.transform));
      const Points xe = unit.apply(make_deformer(ec.mesh, ec.edit,
                                                 opts(method, "multifrontal_refined", mode, exact::kExactTolerance))
                                       ->deform(ec.edit.transform));
      const FactorStats& st = mixed->systems().front().factor;
      EXPECT_GT(st.iterations, 0);
      EXPECT_LE(st.last_correction, tolerance);
      EXPECT_WITHIN(exact::max_rel(xm, xe), exact::refined_bound(tolerance));
    }
}

// The plane is left out for time: its TF system is the largest (40k vertices; its serial float solves take seconds).
INSTANTIATE_TEST_SUITE_P(Cases, MixedBs08, ::testing::Values("cylinder", "bar", "cactus"));

TEST(MixedBs08Cylinder, AnIterationCapItCannotMeetIsASolverError) {
  const EditCase ec = load_edit_case((bs08_dir() / "cylinder").string());
  DeformOptions o = opts("tf", "multifrontal_mixed", ConstraintMode::Soft);
  o.solver_options.max_iterations = 1;
  o.solver_options.tolerance = 1e-14;
  const auto d = make_deformer(ec.mesh, ec.edit, o);
  EXPECT_THROW(d->deform(ec.edit.transform), SolverError);
}

}  // namespace
}  // namespace db
