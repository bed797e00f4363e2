#include "harness/runner.h"

#include <malloc.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "harness/machine_rates.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "mesh/subdivision.h"

namespace db::harness {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kLimitFlag = "--address-space-limit=";

double load_average() {
  std::ifstream la("/proc/loadavg");
  double x = kNaN;
  la >> x;
  return x;
}

// One fresh child: its result line, or an error result saying why there is none.
CellResult run_once(const std::string& exe, const CellSpec& spec, const RunOptions& o) {
  ::malloc_trim(0);  // the forked image counts in the child's ru_maxrss: hand freed heap back first
  const double parent_rss = static_cast<double>(current_rss_bytes());
  std::vector<std::string> argv{exe, "--cell"};
  if (o.address_space_bytes > 0) argv.push_back(kLimitFlag + std::to_string(o.address_space_bytes));
  for (auto& a : spec.to_args()) argv.push_back(a);
  const ChildRun c = run_child(argv, o.timeout_s);
  CellResult r;
  bool decoded = false;
  try {
    r = decode_result(c.out);
    decoded = true;
  } catch (const std::exception&) {
  }
  if (!decoded || c.timed_out || c.term_signal) {
    // No trustworthy result line: the child crashed, was killed or was cut off.
    const double vmhwm = decoded ? r.get("peak_rss_bytes") : kNaN;
    r = CellResult{};
    r.status = "error";
    r.message = fmt::format("child {}; stderr: {}", c.describe(), c.stderr_tail(400));
    if (!std::isnan(vmhwm)) r.set("peak_rss_bytes", vmhwm, "bytes");
  }
  r.exit = c.describe();
  r.set("ru_maxrss_bytes", static_cast<double>(c.ru_maxrss_bytes), "bytes");
  r.set("parent_rss_bytes", parent_rss, "bytes");
  r.set("cell_wall_s", c.wall_s, "s");
  r.set("cell_cpu_s", c.user_s + c.sys_s, "s");  // wait4's rusage: the whole child, user + system
  r.set("runs", 1, "count");
  return r;
}

CellResult run_repeated(const std::string& exe, const CellSpec& spec, const RunOptions& o, int repeats) {
  std::vector<CellResult> runs;
  for (int i = 0; i < repeats; ++i) {
    runs.push_back(run_once(exe, spec, o));
    if (!runs.back().ok()) return runs.back();  // a failure is reported as it happened
  }
  CellResult m = median_of(runs);
  m.set("runs", static_cast<double>(runs.size()), "count");
  return m;
}

void add_rates(CellResult& r, const char* when) {
  r.set(fmt::format("blas_dgemm_{}", when), MachineRates::blas_gemm() / 1e9, "GFlop/s");
  r.set(fmt::format("memory_read_{}", when), MachineRates::read_bandwidth() / 1e9, "GB/s");
}

// The budget decision on a prediction: "#over" / "#slow" results, or ok to run.
CellResult over_budget(const Prediction& p, const RunOptions& o) {
  CellResult r;
  if (o.memory_budget_bytes > 0 && p.bytes > o.memory_budget_bytes) {
    r.status = "#over";
    r.message = fmt::format("predicted {:.1f} MiB > memory budget {:.1f} MiB; not attempted", p.bytes / 1048576,
                            o.memory_budget_bytes / 1048576);
  } else if (o.time_budget_s > 0 && p.seconds > o.time_budget_s) {
    r.status = "#slow";
    r.message = fmt::format("predicted {:.3g} s > time budget {:.3g} s; not attempted", p.seconds, o.time_budget_s);
  }
  return r;
}

}  // namespace

CellResult run_cell(const std::string& exe, const CellSpec& spec, const RunOptions& o, const Prediction* p) {
  CellResult r;
  if (p) r = over_budget(*p, o);
  if (r.ok()) {
    const double load = load_average();
    CellResult before;
    if (o.machine_rates) add_rates(before, "before");
    const bool once = p && o.repeat_max_s > 0 && p->seconds > o.repeat_max_s;
    r = run_repeated(exe, spec, o, once ? 1 : std::max(1, o.repeats));
    r.set("load_avg_1m", load, "count");
    for (const Measure& m : before.measures) r.set(m.name, m.value, m.unit);
    if (o.machine_rates && r.ok()) add_rates(r, "after");
  }
  if (p)
    for (const Measure& m : p->measures) r.set(m.name, m.value, m.unit);
  return r;
}

bool is_cell_invocation(int argc, char** argv) { return argc > 1 && std::strcmp(argv[1], "--cell") == 0; }

int cell_main(int argc, char** argv, const std::vector<CellKind>& kinds) {
  // Cells measure cold analyses: an ordering cache (solvers/ordering/ordering_cache.h) would skip the ordering.
  ::unsetenv("DEFORMBENCH_ORDERING_CACHE");
  CellResult r;
  // The spec is parsed inside the guard: a malformed command line is an error result too.
  const CellOutcome o = run_guarded_cell([&] {
    std::vector<std::string> args(argv + 2, argv + argc);
    if (!args.empty() && args.front().rfind(kLimitFlag, 0) == 0) {
      limit_address_space(std::stoull(args.front().substr(std::strlen(kLimitFlag))));
      args.erase(args.begin());
    }
    const CellSpec spec = CellSpec::from_args(args);
    for (const CellKind& k : kinds)
      if (k.name == spec.kind()) {
        r = k.measure(spec);
        return;
      }
    throw UsageError(fmt::format("cell spec: unknown kind '{}'", spec.kind()));
  });
  if (o.status != "ok") {
    r.status = o.status;
    r.message = o.message;
  }
  if (!r.has("peak_rss_bytes")) r.set("peak_rss_bytes", static_cast<double>(peak_rss_bytes()), "bytes");
  std::cout << '\n' << encode_result(r) << std::endl;
  return o.exit_code;
}

CellKind loop_subdivide_kind() {
  return {"loop_subdivide", [](const CellSpec& s) {
            s.check_keys({"in", "levels", "out"});
            Mesh m = read_mesh(s.get("in"));
            m = loop_subdivide(m, static_cast<int>(s.integer("levels", 1, 0, 8)));
            write_mesh(s.get("out"), m);
            CellResult r;
            r.set("vertices", m.num_vertices(), "count");
            return r;
          }};
}

}  // namespace db::harness
