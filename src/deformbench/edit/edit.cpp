#include "edit/edit.h"

#include <algorithm>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

int Edit::count(Role r) const { return static_cast<int>(std::count(roles.begin(), roles.end(), r)); }

std::vector<int> Edit::vertices(Role r) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < roles.size(); ++i)
    if (roles[i] == r) out.push_back(static_cast<int>(i));
  return out;
}

int Edit::target_frames() const {
  const int h = count(Role::Handle);
  return h == 0 ? 0 : static_cast<int>(targets.rows() / h);
}

void validate_edit(const Mesh& mesh, const Edit& edit) {
  const std::string who = edit.name.empty() ? std::string("edit") : "edit '" + edit.name + "'";
  if (static_cast<long>(edit.roles.size()) != mesh.num_vertices())
    throw InputError(fmt::format("{}: selection has {} entries but the mesh has {} vertices", who, edit.roles.size(),
                                 mesh.num_vertices()));
  for (std::size_t i = 0; i < edit.roles.size(); ++i)
    if (edit.roles[i] != Role::Fixed && edit.roles[i] != Role::Free && edit.roles[i] != Role::Handle)
      throw InputError(fmt::format("{}: vertex {} has invalid role {}", who, i, static_cast<int>(edit.roles[i])));
  if (edit.count(Role::Handle) == 0) throw InputError(who + ": the handle is empty");
  if (!edit.transform.allFinite()) throw InputError(who + ": the handle transform has non-finite entries");
  const Eigen::RowVector4d last = edit.transform.row(3);
  if (last != Eigen::RowVector4d(0, 0, 0, 1))
    throw InputError(fmt::format("{}: the handle transform is not affine (last row {} {} {} {}, expected 0 0 0 1)",
                                 who, last(0), last(1), last(2), last(3)));
  const long h = edit.count(Role::Handle), rows = static_cast<long>(edit.targets.rows());
  if (rows % h != 0)
    throw InputError(fmt::format("{}: {} target positions are not a whole number of frames of the handle's {} vertices",
                                 who, rows, h));
  if (!edit.targets.allFinite()) throw InputError(who + ": a target position is not finite");
  if (edit.count(Role::Free) == 0) throw InputError(who + ": no free vertex (the region of interest is only the handle)");
}

}  // namespace db
