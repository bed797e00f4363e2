#pragma once
//! Coating transfer (Sorkine et al. 2004, section 5; the LSE report's second application): the coating of a
//! source patch is the difference between its Laplacian coordinates and those of its smoothed version, written
//! in the smooth surface's local frames (applications/tangent_frames.h). Both patches are mapped onto the unit
//! disk (Tutte, applications/disk_parameterization.h); each target vertex reads the coating at its parameter
//! point, turns it into its own frame and adds it to its Laplacian coordinates; the LSE solve (boundary and the
//! rest of the target fixed) reconstructs the coated target. Both sides use the whole mesh's Laplacian rows,
//! boundary vertices included (1/deg in the mesh, not within the patch), so a surface's own coating put back onto
//! its own smoothed version gives the surface back on any patch, not only a whole mesh.
//!
//! The smoothing is the least-squares mesh of the patch (applications/lse_solve.h with delta = 0 inside: every
//! interior vertex pulled softly, weight w, towards where it is; the boundary fixed): detail at scales where
//! |L|^2 exceeds w^2 is removed, broad shape kept.
#include <vector>

#include "applications/disk_parameterization.h"
#include "applications/disk_patch.h"
#include "applications/lse_solve.h"

namespace db {

struct CoatingOptions {
  double smooth_weight = 0.01;  //!< w of the smoothing: smaller removes broader detail
  //! Multiplies the transferred detail. The detail is also scaled so that it keeps its proportions on a patch of
  //! another size and sampling: by sigma = the ratio of the boundary lengths (target over source), and, since
  //! uniform Laplacian coordinates grow with the square of the vertex spacing h, by rho^2 with
  //! rho = (h_target / h_source) / sigma (h: mean edge length; the source's on its smooth version).
  double amplitude = 1.0;
};

struct Coating {
  DiskPatch patch;
  UV uv;
  Points smooth;  //!< the smoothed patch
  //! Per patch vertex: L(V) - L(smooth), L the source mesh's rows, in the smooth surface's frames (t1, t2, n).
  Points detail;
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
  double scale = 1;      //!< the detail's factor: amplitude x sigma x rho^2 (CoatingOptions::amplitude)
  double sigma = 1;      //!< the boundary-length ratio, target over source
  double detail_error = 0;  //!< |F^T (L(x) - L(target)) - mapped_detail| / |mapped_detail| over interior vertices
  LseReport solve;
  double parameterize_s = 0, map_s = 0;
};

//! Transfers `coating` onto `region` of `target`; the vertices outside the patch's interior stay where they are.
CoatedTarget transfer_coating(const Coating& coating, const Mesh& target, const std::vector<int>& region,
                              const CoatingOptions& options);

}  // namespace db
