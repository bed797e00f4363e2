#pragma once
//! The measurements of one coating transfer or transplant, as named numbers: what `deformbench coat|transplant
//! --csv` writes and the `applications` experiment's cells report (sizes, phase times, detail preservation,
//! boundary continuity), so both name and compute them alike.
#include <string>
#include <utility>
#include <vector>

#include "applications/coating_transfer.h"
#include "applications/transplant.h"

namespace db {

using NamedValues = std::vector<std::pair<std::string, double>>;

//! `target` is the mesh before the transfer; `total_s` the wall time of extract + transfer.
NamedValues coat_measures(const Coating& coating, const CoatedTarget& t, const Mesh& target, double total_s);
//! `target` is the mesh before the graft; `total_s` the wall time of transplant_patch.
NamedValues transplant_measures(const Transplant& t, const Mesh& target, double total_s);

}  // namespace db
