#pragma once
//! An edit: which vertices move with the handle, which stay fixed, which are free (the region of interest),
//! and the handle transform. Readers for Botsch-Sorkine .sel/.def files, vertex index lists and geometric
//! selections live in edit_io.h / selection.h.
#include <cstdint>
#include <string>
#include <vector>

#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

//! Botsch-Sorkine 2008 status codes: 0 fixed (outside the region), 1 free (region of interest), 2 handle.
enum class Role : std::uint8_t { Fixed = 0, Free = 1, Handle = 2 };

//! Most frames one run interpolates (--frames, and the frames of an edit's targets file): every frame's phase times
//! are kept for the medians.
constexpr long long kMaxFrames = 100000;

struct Edit {
  std::string name;         //!< for result rows
  std::vector<Role> roles;  //!< one per vertex
  Mat4 transform = Mat4::Identity();  //!< handle transform, applied to original handle positions
  //! A general drag instead of one transform (`targets = FILE` in a .edit file; empty: none): the target position
  //! of every handle vertex in every frame, frame f's k-th handle vertex (ascending index) in row f h + k.
  Points targets;

  //! Frames the targets give (rows / handle count), 0 without targets.
  int target_frames() const;

  int count(Role r) const;
  std::vector<int> vertices(Role r) const;
};

//! Checks the edit against its mesh and throws InputError naming the problem: size mismatch, empty handle,
//! a transform that is not finite or not affine (last row != 0 0 0 1), nothing free to solve for, targets whose
//! count is not a whole number of frames of the handle or that are not finite.
void validate_edit(const Mesh& mesh, const Edit& edit);

//! Applies an affine 4x4 transform to a point.
inline Vec3 apply(const Mat4& T, const Vec3& p) { return T.topLeftCorner<3, 3>() * p + T.topRightCorner<3, 1>(); }

}  // namespace db
