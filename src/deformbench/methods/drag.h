#pragma once
//! A handle drag: the frames of an interactive edit interpolate the identity to the final handle transform, or
//! (an edit with per-vertex targets) take its target frames in turn. drag() runs them and keeps every frame's
//! phase times: the one loop of the command line and the deform cell.
#include <functional>
#include <vector>

#include "core/spread.h"
#include "solvers/base/types.h"
#include "edit/edit.h"
#include "methods/deformer.h"

namespace db {

//! Fraction f in [0,1] of T: a rigid T is interpolated by axis-angle and linear translation; any other
//! linear part is blended linearly (a rotation cannot be extracted meaningfully).
Mat4 interpolate_transform(const Mat4& T, double f);

//! Frame f (1..frames) of the edit's drag: its per-vertex targets' frame (f - 1) mod their count when it has
//! targets, else its handle transform interpolated to f / frames.
Points deform_frame(Deformer& d, const Edit& e, long long f, long long frames);

//! Every frame's phase times (seconds, in frame order; PhaseTimes) and the last frame's positions.
struct Drag {
  std::vector<double> frame, rhs, solve, write, response, orthonormalize;
  std::vector<double> frame_cpu;  //!< CPU seconds of this process per frame (all threads; core/timer.h)
  Points V;                       //!< the last frame's positions, #V by 3
};

//! Called after frame f (1..frames) of a drag: e.g. core/progress.h's Progress.
using FrameDone = std::function<void(long long f)>;

//! Runs frames 1..frames of the edit's drag (deform_frame) on `d`, in its current frame mode; `done` (if any)
//! after each frame, outside the timed phases.
Drag drag(Deformer& d, const Edit& e, long long frames, const FrameDone& done = {});

}  // namespace db
