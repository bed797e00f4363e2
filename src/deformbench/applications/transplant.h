#pragma once
//! Transplanting (Sorkine et al. 2004, section 5; the LSE report's third application): a source patch is grafted
//! onto a region of a target surface, and the two meshes are joined.
//!
//! Both patches are mapped onto the unit disk (Tutte). The target's region is cut out (its boundary loop stays);
//! the source patch keeps its own vertices and triangles and sits inside the hole at parameter radius rho (the
//! radius of the region's first inner ring), placed by the similarity that best fits its boundary onto the
//! target surface there (Umeyama). Ears are trimmed off both regions first (Ears::Trim). The band between the
//! hole's loop and the source's boundary is zippered (applications/zipper.h) by parameter angle, or by the shorter
//! diagonal avoiding folds when that band folds less in the target's shape. The LSE solve, with the target outside the hole fixed, then asks each source vertex
//! for Laplacian coordinates blended from the target surface's (resampled at its parameter point: the shape the
//! target had there) at the seam to the placed source's inside the transition zone, so both details meet
//! without a crease. The result has the target's kept vertices and all the source patch's.
//!
//! When the placed source boundary coincides with the hole's loop vertex for vertex (a patch grafted where it was
//! cut from), the loops are welded instead of zippered (a band between coincident loops would have zero area):
//! the source's boundary vertices are the target's, rho = 1.
#include <vector>

#include "applications/disk_patch.h"
#include "applications/lse_solve.h"
#include "applications/seam_metrics.h"

namespace db {

struct TransplantOptions {
  //! Width of the transition zone as a fraction of the source's parameter disk radius: blend weight 0 at its
  //! boundary, 1 from 1 - zone inwards (smoothstep between).
  double zone = 0.3;
};

struct Transplant {
  //! The joined mesh: vertices [0, kept_vertices) are the target's outside the hole (in the target's order, ids in
  //! `kept`), then the source patch's (local order; its boundary left out when welded); faces: the target's kept
  //! ones, the source patch's, then the band's `band_faces`.
  Mesh result;
  DiskPatch source_patch, patch;  //!< the source patch and the target region (the hole)
  std::vector<int> kept;          //!< result vertex -> target vertex, for the kept target vertices
  std::vector<int> source_in_result;  //!< source patch vertex -> result vertex
  int kept_vertices = 0, band_faces = 0;
  bool welded = false;            //!< the loops coincided and were welded (no band)
  bool band_by_diagonal = false;  //!< the band was zippered by the shorter diagonal (else by parameter angle)
  double rho = 1;                 //!< the parameter radius the source patch was placed at
  Points placed;                  //!< per result vertex: the start (kept target, source placed by the similarity)
  std::vector<double> blend;      //!< per source patch vertex: the source's share of its Laplacian coordinates
  double scale = 1;               //!< the placing similarity's scale
  double detail_error = 0;        //!< |L(x) - L(placed)| / |L(placed)| over the source vertices with blend 1
  int core_vertices = 0;          //!< source vertices with blend 1
  SeamAngles seam_before;         //!< across the region's boundary in the target
  SeamAngles seam_after;          //!< across every edge of the band (welded: the seam loop)
  LseReport solve;
  double parameterize_s = 0, map_s = 0;
};

//! Grafts `source_region` of `source` onto `target_region` of `target` (disk patches: extract_disk_patch's errors).
Transplant transplant_patch(const Mesh& source, const std::vector<int>& source_region, const Mesh& target,
                            const std::vector<int>& target_region, const TransplantOptions& options);

}  // namespace db
