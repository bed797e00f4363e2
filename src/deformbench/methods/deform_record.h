#pragma once
//! The record of one deformation: its columns, named once, for the command line's CSV row (`deformbench deform
//! --csv`) and the deform cell's measures (harness/deform_cell.h). Each caller appends what only it sees (the
//! command line: ranks and peak memory per rank; the cell: CPU times, held bytes, handle frames).
#include <string>
#include <vector>

#include "edit/edit.h"
#include "mesh/mesh.h"
#include "methods/deform_options.h"
#include "methods/deformer.h"
#include "methods/drag.h"

namespace db {

//! One column: a number with its unit ("s", "bytes", "count", ...), or a text (unit "text").
struct RecordField {
  std::string name;
  double value = 0;
  std::string unit;
  std::string text;
  bool is_text() const { return unit == "text"; }
};
using DeformRecord = std::vector<RecordField>;

//! Adds a number.
void add_number(DeformRecord& r, const std::string& name, double value, const std::string& unit);
//! Adds a text.
void add_text(DeformRecord& r, const std::string& name, const std::string& text);
//! Adds a timed measure over repeats: NAME_s (the median), NAME_min_s, NAME_max_s and NAME_reps (core/spread.h;
//! the names every result table gives a spread). `name` ends in "_s".
void add_spread(DeformRecord& r, const std::string& name, const std::vector<double>& samples);

//! The columns, in order: mesh, edit, method, weights, constraints, build, backend, ordering_used,
//! factor_storage, drag, frame_mode, precision (texts); vertices, faces, handle, fixed, n, nnz, nnz_factor,
//! factor_flops, factor_top_flops, min_pivot_ratio (of the first system); build_s, analyze_s, factorize_s,
//! factorize_top_s (the first system's FactorStats::top_seconds), init_s, precompute_s, frames; frame_s, rhs_s,
//! solve_s, write_s, response_s (medians over the drag's frames, each with its spread: NAME_min_s, NAME_max_s,
//! NAME_reps); response_bytes, matrix_bytes, factor_bytes; refine_iterations, refine_residual, refine_correction,
//! refine_tolerance. NaN where not measured: precompute_s, response_s and response_bytes in full frame mode,
//! refine_* with a backend that does not refine. `o`: the resolved options.
DeformRecord deform_record(const Mesh& mesh, const Edit& edit, const DeformOptions& o, const Deformer& d,
                           const Drag& g);

}  // namespace db
