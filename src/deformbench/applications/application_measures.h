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

//! Name and value; NaN where the measurement does not apply to this application (a coating's columns in a
//! transplant's row): an empty CSV cell.
using NamedValues = std::vector<std::pair<std::string, double>>;

//! Whether a coating keeps its size: the normal heights of the coating on the target, (result - target) . n over
//! the target patch (n: the target's vertex normals), against the source's, (V - smooth) . n over the source
//! patch (n: the smooth surface's), times sigma (not times the amplitude: a coating at amplitude A gives about A).
//! Two ratios, 1 for a coating that arrives at its size: of the
//! largest |height|, and of the root mean square height weighted by vertex area (a third of the faces around;
//! so that a patch's sampling does not weigh in, only how much of its surface the coating covers how high).
struct CoatingAmplitude {
  double max_ratio = 0, rms_ratio = 0;
};
CoatingAmplitude coating_amplitude(const Coating& coating, const CoatedTarget& t, const Mesh& target);

//! `target` is the mesh before the transfer; `total_s` the wall time of extract + transfer.
NamedValues coat_measures(const Coating& coating, const CoatedTarget& t, const Mesh& target, double total_s);
//! `target` is the mesh before the graft; `total_s` the wall time of transplant_patch.
NamedValues transplant_measures(const Transplant& t, const Mesh& target, double total_s);

}  // namespace db
