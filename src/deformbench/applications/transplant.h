#pragma once
//! Transplanting (Sorkine et al. 2004, section 5; the LSE report's third application): a source patch is grafted
//! onto a region of a target surface. Both are mapped onto the unit disk (Tutte); each target vertex of the
//! region takes the source surface's point at its parameter position, so the region's boundary is joined to the
//! target by construction; the source shape is placed by the similarity that best fits its boundary to the
//! region's (Umeyama). The LSE solve then asks, over the region, for Laplacian coordinates blended from the
//! target's (at the boundary) to the placed source's (inside the transition zone), with the rest of the target
//! fixed, so the graft's detail and the target's meet without a crease.
//!
//! The graft is resampled on the target's connectivity (no zippering of two boundaries): its detail is kept
//! down to the target region's vertex spacing.
#include <vector>

#include "applications/disk_patch.h"
#include "applications/lse_solve.h"

namespace db {

struct TransplantOptions {
  //! Width of the transition zone as a fraction of the parameter disk's radius: blend weight 0 at the region's
  //! boundary, 1 from 1 - zone inwards (smoothstep between).
  double zone = 0.3;
};

struct Transplant {
  Mesh result;              //!< the whole target with the graft
  DiskPatch source_patch, patch;  //!< the source patch and the target region
  Points placed;            //!< per target patch vertex: the source point mapped to it, placed by the similarity
  std::vector<double> blend;  //!< per target patch vertex: the source's share of its Laplacian coordinates
  double scale = 1;         //!< the similarity's scale
  double detail_error = 0;  //!< |L(x) - L(placed)| / |L(placed)| over the vertices with blend 1
  int core_vertices = 0;    //!< vertices with blend 1
  LseReport solve;
  double parameterize_s = 0, map_s = 0;
};

//! Grafts `source_region` of `source` onto `target_region` of `target` (disk patches: extract_disk_patch's errors).
Transplant transplant_patch(const Mesh& source, const std::vector<int>& source_region, const Mesh& target,
                            const std::vector<int>& target_region, const TransplantOptions& options);

}  // namespace db
