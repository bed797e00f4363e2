#include "mesh/subdivision.h"

// OpenMesh's default-constructed VectorT trips -Wmaybe-uninitialized inside its own headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#pragma GCC diagnostic pop
#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

namespace {
// Double-precision points: the default traits use float, which would round every subdivided mesh.
struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
}  // namespace

Mesh loop_subdivide(const Mesh& m, int levels) {
  if (levels < 0) throw InputError(fmt::format("loop_subdivide: levels must be >= 0 (got {})", levels));
  Mesh out = m;
  out.name = fmt::format("{}_loop{}", m.name, levels);
  if (levels == 0) return out;

  OMesh om;
  om.reserve(m.num_vertices(), 3 * m.num_vertices(), m.num_faces());
  std::vector<OMesh::VertexHandle> vh(m.num_vertices());
  for (int i = 0; i < m.num_vertices(); ++i) vh[i] = om.add_vertex(OMesh::Point(m.V(i, 0), m.V(i, 1), m.V(i, 2)));
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (m.F(f, c) < 0 || m.F(f, c) >= m.num_vertices())
        throw InputError(fmt::format("loop_subdivide: face {} has index {} out of range", f, m.F(f, c)));
    if (!om.add_face(vh[m.F(f, 0)], vh[m.F(f, 1)], vh[m.F(f, 2)]).is_valid())
      throw InputError(fmt::format("loop_subdivide: mesh '{}': face {} ({} {} {}) breaks the oriented 2-manifold "
                                   "(non-manifold or inconsistently oriented)",
                                   m.name, f, m.F(f, 0), m.F(f, 1), m.F(f, 2)));
  }

  OpenMesh::Subdivider::Uniform::LoopT<OMesh, double> loop;
  loop.attach(om);
  const bool ok = loop(static_cast<std::size_t>(levels));
  loop.detach();
  if (!ok) throw InputError(fmt::format("loop_subdivide: OpenMesh failed on mesh '{}'", m.name));

  out.V.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
  for (const auto v : om.vertices()) {
    const auto& p = om.point(v);
    out.V.row(v.idx()) << p[0], p[1], p[2];
  }
  out.F.resize(static_cast<Eigen::Index>(om.n_faces()), 3);
  for (const auto f : om.faces()) {
    int c = 0;
    for (const auto v : om.fv_range(f)) out.F(f.idx(), c++) = v.idx();
  }
  return out;
}

}  // namespace db
