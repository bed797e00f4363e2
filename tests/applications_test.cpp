// Coating transfer and transplanting (src/deformbench/applications/): the exactness properties the issue names,
// the parameterization's bijectivity, the transferred detail, and the refusals of non-disk or empty patches.
#include <gtest/gtest.h>

#include <iostream>
#include <numeric>

#include "applications/coating_transfer.h"
#include "applications/disk_parameterization.h"
#include "applications/disk_patch.h"
#include "applications/parameter_map.h"
#include "applications/transplant.h"
#include "edit/selection.h"
#include "test_util.h"

namespace db {
namespace {

std::vector<int> all_vertices(const Mesh& m) {
  std::vector<int> v(static_cast<std::size_t>(m.num_vertices()));
  std::iota(v.begin(), v.end(), 0);
  return v;
}

Mesh bumpy() { return make_bumpy_plane(32, 32, 2.0, 0.08, 3); }
Mesh flat() { return make_bumpy_plane(24, 24, 2.0, 0.0, 1); }

TEST(DiskPatch, CutsTheRegionAndTracesOneLoop) {
  const Mesh m = bumpy();
  const DiskPatch p = extract_disk_patch(m, select_sphere(m, Vec3(0, 0, 0), 0.5), "target");
  EXPECT_GT(p.mesh.num_faces(), 0);
  EXPECT_EQ(p.parent.size(), static_cast<std::size_t>(p.num_vertices()));
  for (int l = 0; l < p.num_vertices(); ++l) EXPECT_EQ(p.mesh.V.row(l), m.V.row(p.parent[l]));
  const int nb = static_cast<int>(std::count(p.on_boundary.begin(), p.on_boundary.end(), 1));
  EXPECT_EQ(nb, static_cast<int>(p.boundary.size()));
}

TEST(DiskPatch, RefusesWhatIsNoDisk) {
  const Mesh plane = flat();
  expect_input_error([&] { extract_disk_patch(plane, {0, 1}, "source"); }, "no whole face");
  expect_input_error([&] { extract_disk_patch(plane, {0, 1, 100000}, "source"); }, "out of range");
  // An annulus: the plane without the faces around its centre.
  std::vector<int> ring;
  for (int v = 0; v < plane.num_vertices(); ++v)
    if (plane.V.row(v).norm() > 0.3) ring.push_back(v);
  expect_input_error([&] { extract_disk_patch(plane, ring, "target"); }, "more than one loop");
  // Two pieces: two opposite corners.
  std::vector<int> corners;
  for (int v = 0; v < plane.num_vertices(); ++v)
    if (std::abs(plane.V(v, 0)) > 0.7 && std::abs(plane.V(v, 1)) > 0.7 && plane.V(v, 0) * plane.V(v, 1) > 0)
      corners.push_back(v);
  expect_input_error([&] { extract_disk_patch(plane, corners, "target"); }, "2 separate pieces");
  // A closed surface has no boundary; an open tube has two loops.
  const Mesh box = make_bar(3, 3, 3, 1, 1, 1);
  expect_input_error([&] { extract_disk_patch(box, all_vertices(box), "source"); }, "no boundary");
  const Mesh t = tube();
  expect_input_error([&] { extract_disk_patch(t, all_vertices(t), "source"); }, "more than one loop");
}

TEST(TutteParameterization, IsBijectiveOntoTheDisk) {
  const Mesh m = bumpy();
  const DiskPatch p = extract_disk_patch(m, all_vertices(m), "source");
  const UV uv = tutte_parameterization(p);
  for (int v : p.boundary) EXPECT_NEAR(uv.row(v).norm(), 1.0, 1e-12);
  for (int f = 0; f < p.mesh.num_faces(); ++f) {  // every triangle keeps its orientation: no fold
    const Eigen::Vector2d a = uv.row(p.mesh.F(f, 0)), b = uv.row(p.mesh.F(f, 1)), c = uv.row(p.mesh.F(f, 2));
    const Eigen::Vector2d e1 = b - a, e2 = c - a;
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0) << "face " << f;
  }
  // Each vertex is found in a face it belongs to, with barycentric weight 1 at itself.
  const auto at = locate_in_parameter_domain(uv, p.mesh.F, uv);
  const Points back = interpolate(at, p.mesh.F, p.mesh.V);
  EXPECT_LT((back - p.mesh.V).cwiseAbs().maxCoeff(), 1e-12);
}

// The test: the surface's own coating onto its own smooth version gives the surface back.
TEST(CoatingTransfer, OwnCoatingOntoOwnSmoothVersionReconstructs) {
  const Mesh m = bumpy();
  const CoatingOptions o;
  const Coating c = extract_coating(m, all_vertices(m), o);
  EXPECT_GT(rel_max(c.smooth, m.V), 0.01);  // the smoothing removed the bumps
  Mesh smooth = m;  // the smooth patch back in the mesh's numbering
  for (int l = 0; l < c.patch.num_vertices(); ++l) smooth.V.row(c.patch.parent[l]) = c.smooth.row(l);
  const CoatedTarget t = transfer_coating(c, smooth, all_vertices(smooth), o);
  EXPECT_DOUBLE_EQ(t.scale, 1.0);
  EXPECT_LT(rel_max(t.result.V, m.V), 1e-8);
  EXPECT_LT(t.detail_error, 1e-8);
}

TEST(CoatingTransfer, PutsTheBumpsOnAFlatPatch) {
  const Mesh src = bumpy(), dst = flat();
  const CoatingOptions o;
  const Coating c = extract_coating(src, all_vertices(src), o);
  const CoatedTarget t = transfer_coating(c, dst, select_sphere(dst, Vec3(0, 0, 0), 0.8), o);
  // Heights appear inside the region only, about as high as the source's bumps, and the solve meets the mapped
  // Laplacian coordinates up to what the fixed boundary allows.
  double detail_h = 0;  // the source's bumps above its smooth version
  for (int l = 0; l < c.patch.num_vertices(); ++l)
    detail_h = std::max(detail_h, std::abs(c.patch.mesh.V(l, 2) - c.smooth(l, 2)));
  const double h = t.result.V.col(2).cwiseAbs().maxCoeff(), source_h = t.sigma * detail_h;
  std::cout << "height " << h << " of the scaled source's " << source_h << ", detail error " << t.detail_error << "\n";
  EXPECT_GT(h, 0.4 * source_h);
  EXPECT_LT(h, 1.5 * source_h);
  for (int v = 0; v < dst.num_vertices(); ++v)
    if (dst.V.row(v).norm() > 0.81) {
      EXPECT_EQ(t.result.V.row(v), dst.V.row(v));
    }
  EXPECT_LT(t.detail_error, 0.2);
}

// The test: a patch grafted onto the surface it was cut from leaves it unchanged.
TEST(Transplant, PatchOntoItsOwnSurfaceLeavesItUnchanged) {
  const Mesh m = bumpy();
  const std::vector<int> region = select_sphere(m, Vec3(0.1, -0.2, 0), 0.7);
  const Transplant t = transplant_patch(m, region, m, region, TransplantOptions{});
  EXPECT_NEAR(t.scale, 1.0, 1e-12);
  EXPECT_LT(rel_max(t.result.V, m.V), 1e-9);
  EXPECT_GT(t.core_vertices, 0);
}

TEST(Transplant, GraftsTheSourceShapeAndKeepsTheRest) {
  const Mesh src = bumpy(), dst = flat();
  const std::vector<int> sr = select_sphere(src, Vec3(0, 0, 0), 0.9), tr = select_sphere(dst, Vec3(0, 0, 0), 0.6);
  const Transplant t = transplant_patch(src, sr, dst, tr, TransplantOptions{});
  EXPECT_GT(t.result.V.col(2).cwiseAbs().maxCoeff(), 0.01);
  for (int v = 0; v < dst.num_vertices(); ++v)
    if (dst.V.row(v).norm() > 0.61) {
      EXPECT_EQ(t.result.V.row(v), dst.V.row(v));
    }
  EXPECT_LT(t.detail_error, 0.2);
}

TEST(CoatingTransfer, RefusesACoatingWhoseArraysDisagree) {
  const Mesh m = flat();
  Coating c = extract_coating(m, all_vertices(m), CoatingOptions{});
  c.detail.conservativeResize(c.detail.rows() - 1, 3);
  expect_input_error([&] { transfer_coating(c, m, all_vertices(m), CoatingOptions{}); }, "detail vectors");
}

TEST(LseSolve, RefusesMismatchedSizes) {
  const Mesh m = flat();
  const std::vector<Constraint> kinds(static_cast<std::size_t>(m.num_vertices()), Constraint::Hard);
  expect_input_error([&] { solve_lse(m, kinds, 1.0, Points::Zero(3, 3), m.V); }, "Laplacian coordinates");
}

}  // namespace
}  // namespace db
