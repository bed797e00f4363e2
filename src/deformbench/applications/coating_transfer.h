#pragma once
//! Coating transfer (Sorkine et al. 2004, section 5; the LSE report's second application): the coating of a
//! source patch is the difference between its Laplacian coordinates and those of its smoothed version, written
//! in the smooth surface's local frames (applications/tangent_frames.h). Both the smooth source patch and the
//! target patch are mapped onto the unit disk (applications/disk_parameterization.h; the source's map is taken on
//! the smooth surface the detail sits on, so that a surface's own smooth version maps exactly as its coating
//! does); each target vertex reads the coating at its parameter point, turns it into its own frame and adds it to
//! its Laplacian coordinates; the LSE solve (boundary and the rest of the target fixed) reconstructs the coated
//! target. Both sides use the whole mesh's Laplacian rows, boundary vertices included (1/deg in the mesh, not
//! within the patch), so a surface's own coating put back onto its own smoothed version gives the surface back on
//! any patch, not only a whole mesh.
//!
//! Two encodings of the detail (CoatingOptions::encoding):
//!  - height (the default): the displacement V - smooth itself, in the frames; the target's vertices are moved by
//!    it (scaled by sigma) and the LSE solve takes the Laplacian coordinates of the moved surface. The coating's
//!    normal heights arrive as they were whatever the two meshes' sampling, since a displacement does not depend
//!    on the spacing of the vertices around it.
//!  - laplacian (Sorkine et al.'s): L(V) - L(smooth). Uniform Laplacian coordinates measure the detail against
//!    the local vertex spacing, and the height the solve rebuilds from them grows with the square of how much the
//!    map stretches the coating across the target; the global rho^2 below corrects only the mean, so on irregular
//!    targets the coating comes out taller or flatter than the source's (results/applications.md measures each).
//!
//! The smoothing is the least-squares mesh of the patch (applications/lse_solve.h with delta = 0 inside: every
//! interior vertex pulled softly, weight w, towards where it is; the boundary fixed): detail at scales where
//! |L|^2 exceeds w^2 is removed, broad shape kept.
#include <vector>

#include "applications/disk_parameterization.h"
#include "applications/disk_patch.h"
#include "applications/lse_solve.h"

namespace db {

enum class DetailEncoding { Height, Laplacian };
const EnumText<DetailEncoding>& enum_text(DetailEncoding);  //!< "height" | "laplacian"

struct CoatingOptions {
  double smooth_weight = 0.01;  //!< w of the smoothing: smaller removes broader detail
  //! Multiplies the transferred detail. The detail is also scaled so that it keeps its proportions on a patch of
  //! another size: by sigma = the ratio of the boundary lengths (target over source); laplacian encoding also by
  //! rho^2, rho = (h_target / h_source) / sigma (h: mean edge length; the source's on its smooth version), since
  //! uniform Laplacian coordinates grow with the square of the vertex spacing.
  double amplitude = 1.0;
  //! The maps of both patches onto the disk. Uniform by default: with the height encoding it is the one map of
  //! the three whose coating keeps its area-weighted size on every target of the applications experiment
  //! (results/applications.md). The displacement's height arrives unchanged under any map; how much of the
  //! target it covers follows how the two maps' area distortions differ, which the geometric maps (mean value,
  //! cotangent: conformal-like, so their scale varies across a curved cap) do not keep as close.
  DiskMap map = DiskMap::Uniform;
  DetailEncoding encoding = DetailEncoding::Height;
};

struct Coating {
  DiskPatch patch;
  UV uv;          //!< the smoothed patch's map onto the disk
  Points smooth;  //!< the smoothed patch
  //! Per patch vertex, in the smooth surface's frames (t1, t2, n): V - smooth (height encoding) or
  //! L(V) - L(smooth), L the source mesh's rows (laplacian encoding).
  Points detail;
  DetailEncoding encoding = DetailEncoding::Height;
  double boundary_length = 0, mean_edge = 0;
  LseReport smoothing;
  double parameterize_s = 0;
};

//! The coating of `region` of `source` (a disk patch: extract_disk_patch's errors).
Coating extract_coating(const Mesh& source, const std::vector<int>& region, const CoatingOptions& options);

struct CoatedTarget {
  Mesh result;           //!< the whole target, coated within its patch
  DiskPatch patch;       //!< the target patch
  Points mapped_detail;  //!< per target patch vertex: the coating it received (scaled), in its frame
  double scale = 1;      //!< the detail's factor: amplitude x sigma (x rho^2: laplacian encoding)
  double sigma = 1;      //!< the boundary-length ratio, target over source
  //! |F^T (E(x) - E(target)) - mapped_detail| / |mapped_detail| over interior vertices, E the encoding (positions
  //! or their Laplacian coordinates): how much of the mapped coating the solved surface carries.
  double detail_error = 0;
  LseReport solve;
  double parameterize_s = 0, map_s = 0;
};

//! `source` with the coating's patch replaced by its smooth version: the target of a self-coating, which must give
//! `source` back.
Mesh own_smooth_version(const Mesh& source, const Coating& coating);

//! Transfers `coating` onto `region` of `target`; the vertices outside the patch's interior stay where they are.
CoatedTarget transfer_coating(const Coating& coating, const Mesh& target, const std::vector<int>& region,
                              const CoatingOptions& options);

}  // namespace db
