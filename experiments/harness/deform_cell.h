#pragma once
//! The deformation cell (kind "deform"): one mesh and edit, one method / build / backend, a handle drag over
//! `frames` frames (an edit with per-vertex targets, `targets = FILE`: its frames in turn, cycling). Used by
//! Table 2-1 (the thesis edit on a mesh, soft constraints) and the edit cases (an edit file with the library's
//! defaults); the tracking suite can list such cells as data.
//!
//! Spec keys (DeformCell::to_spec / from_spec): the cell's own - model, mesh | edit, frames, handle, anchors, drag,
//! memory_budget_bytes, out_mesh, handle_frames - and any key of the deform options (methods/deform_options.h:
//! method, build, backend, ordering, constraints, factor_dir, weights, lri_frames, ...; the cell's defaults are
//! method=tf backend=multifrontal).
//! Measures: the deformation's record (methods/deform_record.h: vertices, faces, handle, fixed, n, nnz,
//! nnz_factor, factor_flops, min_pivot_ratio, build_s, analyze_s, factorize_s, init_s, frames, frame_s, rhs_s,
//! solve_s, write_s, ... - medians over the frames, each with its spread: frame_min_s, frame_max_s, frame_reps;
//! matrix_bytes, factor_bytes; texts mesh, method, constraints, build, backend, ordering_used, ...), then fps,
//! init_cpu_s and frame_cpu_s (CPU time of this process, core/timer.h: make_deformer; median per frame),
//! held_bytes:<matrix>, held_total_bytes, peak_rss_bytes (VmHWM), baseline_rss_bytes (after reading the mesh),
//! mean_displacement (last frame, / bbox diagonal).
//! With handle_frames=1, after the drag the same factored systems switch to handle-mode frames
//! (Deformer::precompute_handle_frames) and the drag runs again: precompute_s, precompute_cpu_s (its CPU
//! time, all threads), init_precompute_s,
//! frame_handle_s, response_s, handle_rhs_s, handle_solve_s, orthonormalize_s (medians with their spread; LRI's
//! position part stays per frame), fps_handle, response_bytes, handle_vs_full (largest distance between the
//! two modes' last frames / bbox diagonal), peak_rss_handle_bytes (VmHWM after them; peak_rss_bytes is taken
//! before), memory_read (GB/s, MachineRates::read_bandwidth right after) and
//! response_pass_s (response_bytes at that rate: the least a handle frame could take).
#include <cstddef>
#include <string>
#include <vector>

#include "harness/cell.h"
#include "harness/runner.h"
#include "harness/thesis_edit.h"
#include "methods/deform_options.h"

namespace db::harness {

struct DeformCell {
  std::string model;  //!< label for result rows ("hand", "armadillo_loop2", "bs08_bar")
  std::string mesh;   //!< a mesh file, deformed by the thesis edit (harness/thesis_edit.h) ...
  std::string edit;   //!< ... or an edit (Botsch-Sorkine stem or .edit file); exactly one of the two
  //! What to deform with (dense builds: a dense backend, "dense_llt"); constraints soft for Table 2-1's cells
  //! (thesis eq. 2-4); solver_options.factor_dir set: the factor out of core.
  DeformOptions options = default_options();
  int frames = 20;
  ThesisEditOptions thesis;                 //!< with `mesh`
  std::size_t memory_budget_bytes = 0;      //!< DeformOptions::memory_budget (the systems layer's own check)
  std::string out_mesh;                     //!< when set, the last frame's mesh is written here
  bool handle_frames = false;               //!< also measure handle-mode frames (issue 16)

  //! The library's defaults but method tf and backend multifrontal.
  static DeformOptions default_options();
  CellSpec to_spec() const;
  //! \throw UsageError on an unknown key, a malformed number, options that do not go together
  //! (resolve_options), or not exactly one of mesh / edit.
  static DeformCell from_spec(const CellSpec& spec);
  //! "hand/tf/structured/multifrontal"
  std::string key() const;
  //! "disk" when the factor is kept out of core, else "memory".
  std::string factor_storage() const { return options.solver_options.factor_dir.empty() ? "memory" : "disk"; }
  std::string method() const { return to_string(options.method); }
  std::string build() const { return to_string(options.build); }
  const std::string& backend() const { return options.solver; }
};

//! Measures a deformation cell in this process. \throw whatever the layers below throw.
CellResult measure_deform_cell(const CellSpec& spec);
inline CellKind deform_kind() { return {"deform", measure_deform_cell}; }

}  // namespace db::harness
