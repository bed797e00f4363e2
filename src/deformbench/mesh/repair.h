#pragma once
//! Turns a real-world triangle soup into what validate_mesh(Manifold::Required) accepts, reporting each change:
//! drops degenerate and duplicate faces, splits non-manifold vertices and edges, removes isolated vertices.
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace db {

struct RepairReport {
  struct Split {
    int vertex;               //!< input index
    std::vector<int> copies;  //!< output indices of the copies added (the first fan keeps the vertex)
  };
  std::vector<std::pair<int, std::string>> degenerate_faces;  //!< input face, why (degenerate_face)
  std::vector<std::pair<int, int>> duplicate_faces;           //!< input face, the earlier face with its corners
  NonManifold non_manifold;                                   //!< after dropping faces, before splitting
  std::vector<Split> splits;
  std::vector<int> isolated_vertices;  //!< input indices removed
  std::vector<int> vertex_map;         //!< input vertex -> output vertex (-1: removed)
  //! Connected components (face_components) of the input and of the output.
  int components_before = 0, components_after = 0;
  //! An output component split off an input component by the repair (each input component keeps its largest).
  struct Piece {
    int faces;      //!< in the piece
    int from;       //!< the input component
    int from_kept;  //!< faces its largest piece keeps
  };
  std::vector<Piece> detached;

  bool changed() const {
    return !degenerate_faces.empty() || !duplicate_faces.empty() || !splits.empty() || !isolated_vertices.empty();
  }
  //! One line of counts ("dropped 2 degenerate faces, ...", or "no change"), with the components before and after
  //! when the repair detached pieces.
  std::string summary() const;
  //! Every change, one per line; at most `max_per_kind` of each kind (0: all), then "... and N more".
  std::vector<std::string> details(std::size_t max_per_kind) const;
};

//! Repairs `in` (indices must be in range and coordinates finite; \throw InputError otherwise). Faces are
//! dropped first (a repeated corner or a relative area under 1e-14, see degenerate_face; then a face with the
//! corners of an earlier one, in any order or orientation). Then each vertex whose faces fall into several fans
//! gets one copy per extra fan. Faces stay joined across an edge with exactly two faces; across an edge with more,
//! in pairs that traverse it in opposite directions: first two faces the rest of the surface connects anyway
//! (a solid's faces at an edge a fin is glued to), then those that meet flattest. So a fin or a second sheet
//! glued to a surface comes off it and the surface stays whole. That splits pinched
//! vertices and leaves no edge with more than two faces. Finally vertices in no face are removed. Kept vertices
//! keep their order, copies follow; faces keep their order and orientation. A mesh that needs nothing comes back
//! unchanged. \throw InputError when no valid face remains.
Mesh repair_mesh(const Mesh& in, RepairReport& report);

}  // namespace db
