#include "harness/thesis_edit.h"

#include <algorithm>
#include <array>
#include <numeric>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "edit/edit_io.h"
#include "edit/selection.h"
#include "edit/transform.h"

namespace db::harness {
namespace {

struct Axes {
  int longest = 0, second = 1;
  Vec3 lo, hi;
};

Axes bbox_axes(const Mesh& mesh) {
  Axes a;
  a.lo = mesh.V.colwise().minCoeff().transpose();
  a.hi = mesh.V.colwise().maxCoeff().transpose();
  const Vec3 ext = a.hi - a.lo;
  std::array<int, 3> order{0, 1, 2};
  // Stable on ties: the lower axis index wins, so the edit is deterministic.
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return ext(x) > ext(y); });
  a.longest = order[0];
  a.second = order[1];
  return a;
}

// Vertex with the extreme coordinate along `axis` (the lowest id among ties).
int extreme_vertex(const Mesh& mesh, int axis, bool maximum) {
  int best = 0;
  for (int v = 1; v < mesh.num_vertices(); ++v) {
    const double c = mesh.V(v, axis), b = mesh.V(best, axis);
    if (maximum ? c > b : c < b) best = v;
  }
  return best;
}

}  // namespace

Edit make_thesis_edit(const Mesh& mesh, const ThesisEditOptions& opt) {
  const int nv = mesh.num_vertices();
  if (nv < 3) throw InputError("thesis edit: the mesh has fewer than 3 vertices");
  if (opt.handle_count < 1 || opt.anchor_count < 1) throw InputError("thesis edit: handle and anchor counts must be >= 1");
  const Axes ax = bbox_axes(mesh);
  const int top = extreme_vertex(mesh, ax.longest, true), bottom = extreme_vertex(mesh, ax.longest, false);
  const std::vector<int> handle =
      select_nearest(mesh, mesh.V.row(top).transpose(), std::min(opt.handle_count, nv - 1));
  std::vector<int> anchors = select_nearest(mesh, mesh.V.row(bottom).transpose(), std::min(opt.anchor_count, nv - 1));
  // Both lists are sorted: drop anchors that are handle vertices.
  std::vector<int> kept;
  std::set_difference(anchors.begin(), anchors.end(), handle.begin(), handle.end(), std::back_inserter(kept));
  if (kept.empty()) throw InputError("thesis edit: every anchor coincides with a handle vertex");
  std::vector<int> roi;  // everything but the anchors; the handle lies inside it
  roi.reserve(nv);
  std::vector<char> is_anchor(nv, 0);
  for (int v : kept) is_anchor[v] = 1;
  for (int v = 0; v < nv; ++v)
    if (!is_anchor[v]) roi.push_back(v);
  Vec3 t = Vec3::Zero();
  t(ax.second) = opt.drag_fraction * bbox_diagonal(mesh.V);
  Edit e = edit_from_lists(nv, roi, handle, translation(t));
  e.name = fmt::format("{}_thesis_h{}_a{}", mesh.name, handle.size(), kept.size());
  return e;
}

std::string describe_thesis_edit(const Mesh& mesh, const ThesisEditOptions& opt) {
  const Axes ax = bbox_axes(mesh);
  const char* names = "xyz";
  return fmt::format(
      "handle: {} vertices nearest the +{} extreme; anchors: {} vertices nearest the -{} extreme; translation "
      "{} x bbox diagonal along {}",
      opt.handle_count, names[ax.longest], opt.anchor_count, names[ax.longest], opt.drag_fraction, names[ax.second]);
}

}  // namespace db::harness
