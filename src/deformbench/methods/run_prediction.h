#pragma once
//! What one deformation run will need, predicted before it starts: peak resident memory and the init time
//! (build + analyze + factorize), from the symbolic analysis of the system it will factor and rates measured on
//! this machine. `deformbench deform` checks the memory part against its budget before building anything;
//! `deformbench advise` skips backends predicted over budget and prints the predictions (--predict-only);
//! exp_predictions sets them against measurements.
//!
//! Memory: the process's resident bytes when the prediction is made (mesh and edit loaded) + what the method
//! allocates per vertex + predict_build_bytes (systems/normal_system.h) + the factor and the factorization's
//! working storage (times a measured ratio) + a measured fixed part. The factor: the backend's own analysis of the
//! vertex graph of the system (unknowns within two edges for lap/tf, one for LRI's edge systems), ordered as the
//! deformer orders it, its nonzeros and flops expanded to the b x b blocks of TF (b = 3) or LRI's frame system.
//! Dense: n^2 doubles, n^3 / 3 flops.
//! Time: each phase a function of its predicted work (PhaseRate), measured on this machine (MachineCalibration:
//! generated planes of two to four sizes deformed with each backend, build and method in fresh processes).
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "edit/edit.h"
#include "methods/deform_options.h"
#include "mesh/mesh.h"
#include "systems/normal_system.h"

namespace db {

//! One phase's time as a function of its work, through the calibration's measured (units, seconds) points: a
//! power law on each segment between neighbouring points (a straight line in log-log), and beyond the ends the
//! end segment's power. Each segment's exponent is clamped to [kMinExponent, kMaxExponent], so a noisy pair of runs
//! cannot make the extrapolation explode; beyond the largest point it is at most 1 (time at most proportional to
//! the work: a superlinear segment is a working set outgrowing a cache, which does not repeat at every larger
//! size). Several sizes matter because the factorizations' rate grows with the front sizes and then levels off:
//! the segment between the two largest sizes is the one that extrapolates.
struct PhaseRate {
  static constexpr double kMinExponent = 0.3, kMaxExponent = 1.3;
  std::vector<std::pair<double, double>> points;  //!< (units, seconds), units ascending and distinct, all > 0
  //! Seconds for `units` of work (0 when uncalibrated or without work); one point: proportional to the work.
  double seconds(double units) const;
  //! The points with units and seconds > 0, sorted; of equal units the later is kept.
  static PhaseRate fit(std::vector<std::pair<double, double>> points);
  //! "units:seconds;units:seconds..." (the calibration file's form) and back. \throw InputError for bad text.
  std::string text() const;
  static PhaseRate parse(const std::string& text);
};

//! One backend's rates for one build and method, measured by deforming generated planes of several sizes with it
//! (advise --calibrate). Work units: build - the predicted stencil multiply-adds (build_flops); analyze - the
//! predictor's own analysis seconds on the same graph with the same ordering (so METIS and AMD are told apart);
//! factorize - the predicted flops (matrix nonzeros where the backend has none).
struct BackendRates {
  PhaseRate build, analyze, factorize;
  //! Peak RSS = base + build bytes + peak_fixed_bytes + peak_per_factor x (factor + workspace bytes): the fixed
  //! part is what a backend holds whatever the size (MUMPS's MPI, a dense backend's LAPACK buffers).
  double peak_per_factor = 1, peak_fixed_bytes = 0;
  //! Flops per second no factorization exceeds (0: no bound): the best the dense LAPACK Cholesky reached in the
  //! calibration (MachineCalibration::find sets it). Why: beyond the largest plane the factorizations' rate still
  //! grows by the last segment's power, but their large fronts run the same BLAS kernels as a dense Cholesky and
  //! level off at its rate.
  double peak_flop_rate = 0;
};

//! Rates per backend, build and method (key "BACKEND/BUILD/METHOD"), and per ordering where a backend's orderings
//! differ in their build and analysis ("BACKEND/BUILD/METHOD/ORDERING": its build and analysis phases are used),
//! with where they were measured.
struct MachineCalibration {
  std::map<std::string, BackendRates> rates;
  std::string provenance;  //!< host, cpu, BLAS core, threads, git sha, timestamp of the calibration
  bool empty() const { return rates.empty(); }
  //! The rates for a backend, build and method (LRI, which is not calibrated, takes TF's): those of the method's
  //! default ordering, with the build and analysis phases of `ordering` where it was calibrated apart. The orderings
  //! differ in the analysis's cost, and in the build's: the structured build runs on one thread beside AMD
  //! (build_structured_while_ordering) and on all of them after METIS. The factorization's rate per flop and the
  //! memory do not depend on the ordering.
  std::optional<BackendRates> find(const std::string& backend, Build build, Method method,
                                   const std::string& ordering = "") const;
  static std::string key(const std::string& backend, Build build, Method method, const std::string& ordering = "");
  //! The best factorization flops per second of the lapack_potrf keys (0 without them).
  double dense_flop_rate() const;
  //! CSV with one row per key; `provenance` in every row.
  void save(const std::string& path) const;
  //! \throw InputError for a malformed file (or one of an older layout). A missing file gives an empty calibration.
  static MachineCalibration load(const std::string& path);
};

struct RunPrediction {
  double base_bytes = 0;       //!< resident when predicting (mesh and edit loaded) + the method's per-vertex data
  double build_bytes = 0;      //!< predict_build_bytes (+ LRI's second system)
  double factor_bytes = 0;     //!< values and indices of the factor(s)
  double workspace_bytes = 0;  //!< the factorization's update matrices (multifrontal), as its analysis reports
  double peak_bytes = 0;       //!< base + build + fixed + (factor + workspace) * peak_per_factor (BackendRates)
  double n = 0, nnz_matrix = 0, factor_nnz = 0, factor_flops = 0, build_flops = 0;
  double analysis_s = 0;       //!< what the predictor's own analysis took
  double build_s = 0, analyze_s = 0, factorize_s = 0, init_s = 0;  //!< NaN without a calibration for the backend
  std::string basis;           //!< what the factor counts come from
};

//! One system's factor, from the backend's symbolic analysis of the system's vertex graph, expanded to its
//! b x b blocks (what predict_run adds up over a method's systems).
struct FactorCount {
  double nnz_matrix = 0;  //!< nonzeros of the system's upper triangle
  double nnz = 0, flops = 0;  //!< of the factor
  double workspace = 0;   //!< bytes of the factorization's working storage besides the factor (update matrices)
  double seconds = 0;     //!< what the analysis took
  std::string backend;    //!< the backend whose analysis counted it (CHOLMOD's supernodal one standing in)
  std::string basis;      //!< what the counts come from
};

//! Counts the factor of a system of `block` x `block` blocks whose vertex graph is `pattern` (upper triangle,
//! interaction_pattern; `num_unknowns` columns) as `o.solver` factors it: `ordered` true, `pattern` is in the order
//! the run factors it (analysed in natural order); else the backend orders it with o.solver_options.ordering, or
//! with its default one when `exact` is false. Iterative backends count no factor (cg_ichol: K's pattern); dense
//! backends, and backends that count nothing before they factorize, are counted by CHOLMOD's supernodal analysis.
FactorCount count_factor(const InteractionPattern& pattern, int num_unknowns, bool ordered, int block,
                         const DeformOptions& o, bool exact);

//! Multiply-adds of the A^T A product of a 1-ring operator (the sparse builds): the sum over the `num_vertices`
//! vertices of (degree + 1)^2, times 2 block^3.
double stencil_flops(const Adjacency& adj, int num_vertices, int block);

//! Predicts runs of one edit with different options: keeps the mesh's adjacency, the resident bytes when it was
//! made (the base of every prediction) and each vertex graph it ordered, so that predicting many backends orders
//! each graph once. Keeps references to `mesh` and `edit`.
class RunPredictor {
 public:
  RunPredictor(const Mesh& mesh, const Edit& edit);
  ~RunPredictor();
  //! As predict_run.
  RunPrediction predict(const DeformOptions& options, const MachineCalibration& calibration, double scale = 1,
                        bool exact_ordering = true);

 private:
  struct Graph {
    Unknowns unk;
    InteractionPattern pattern;
    double seconds = 0;  // building the pattern and ordering it, as the run's analysis counts it (0 unordered)
  };
  const Graph& graph(const DeformOptions& o, int rings, const std::string& ordering);
  double build_bytes(const DeformOptions& o, const Unknowns& unk) const;

  const Mesh& mesh_;
  const Edit& edit_;
  Adjacency adj_;
  double rss_ = 0;
  std::map<std::string, std::unique_ptr<Graph>> graphs_;
};

//! Predicts a run of `edit` on `mesh` with `options` (resolved: resolve_options). `scale` != 1: a mesh of the same
//! shape with `scale` times the vertices by a growth law (nonzeros of K and the build linearly, nnz(L) as n log n,
//! flops as n^1.5: a surface under nested dissection; advise --scale subdivides the mesh first,
//! methods/scaled_edit.h, and leaves the law a factor within [1/2, 2]). `exact_ordering` false: the vertex graph is
//! ordered by AMD whatever the run uses (cheap; `deform`'s budget check), true: as the run orders it.
//! \throw as make_deformer for options that do not go together or a singular constraint set.
RunPrediction predict_run(const Mesh& mesh, const Edit& edit, const DeformOptions& options,
                          const MachineCalibration& calibration, double scale = 1, bool exact_ordering = true);

//! Where this machine's calibration is kept: $DEFORMBENCH_CALIBRATION, else machine_calibration.csv beside the
//! running executable (the build directory: one per build and machine).
std::string calibration_path();

//! /proc/meminfo's MemAvailable in bytes (0 when it cannot be read): deform's default memory budget.
std::size_t available_memory_bytes();

}  // namespace db
