// Deforms every available edit case (the BS08 survey cases, the bundled CGAL cactus edit) with LAP and TF and
// writes one tidy row per (case, method): sizes, phase times, median frame time over a handle drag, bytes.
//   exp_deform_cases --data DIR --shared DIR --out results/deform_cases.csv [--meshes DIR] [--frames N]
#include <algorithm>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "core/args.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/resources.h"
#include "edit/edit_io.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  try {
    const db::Args a = db::parse_args(argc, argv, 1);
    const fs::path data = a.get("--data", "data"), shared = a.get("--shared", "data/bs08");
    const std::string out = a.get("--out", "results/deform_cases.csv");
    const std::string mesh_dir = a.get("--meshes", "");
    const int frames = static_cast<int>(a.number("--frames", 20));
    if (!mesh_dir.empty()) fs::create_directories(mesh_dir);

    std::vector<std::pair<std::string, std::string>> cases;  // (label, spec)
    for (const char* c : {"plane", "cylinder", "bar", "cactus"}) {
      if (fs::exists(shared / (std::string(c) + ".off"))) cases.emplace_back(std::string("bs08_") + c, (shared / c).string());
      else std::cerr << "[deform_cases] skipping BS08 " << c << ": not found under " << shared << "\n";
    }
    const fs::path cgal_cactus = data / "edits" / "cactus_cgal.edit";
    if (fs::exists(cgal_cactus)) cases.emplace_back("cgal_cactus", cgal_cactus.string());
    else std::cerr << "[deform_cases] skipping the CGAL cactus: " << cgal_cactus << " missing (run scripts/data.sh)\n";
    if (cases.empty()) throw db::InputError("no edit case found");

    std::cerr << "[deform_cases] " << db::provenance_summary() << "\n";
    db::CsvTable csv;
    for (const auto& [label, spec] : cases) {
      const db::EditCase ec = db::load_edit_case(spec);
      for (const char* method : {"lap", "tf"}) {
        db::DeformOptions o;
        o.method = method;
        auto d = db::make_deformer(ec.mesh, ec.edit, o);
        std::vector<double> ft;
        db::Points V;
        for (int f = 1; f <= frames; ++f) {
          V = d->deform(db::interpolate_transform(ec.edit.transform, static_cast<double>(f) / frames));
          ft.push_back(d->times().frame());
        }
        std::sort(ft.begin(), ft.end());
        const double median = ft[ft.size() / 2];
        if (!mesh_dir.empty()) {
          db::Mesh m = ec.mesh;
          m.V = V;
          db::write_mesh((fs::path(mesh_dir) / fmt::format("{}_{}.ply", label, method)).string(), m);
        }
        const auto& t = d->times();
        const auto& s = d->systems().front();
        csv.add({{"case", label},
                 {"mesh", ec.mesh.name},
                 {"vertices", std::to_string(ec.mesh.num_vertices())},
                 {"faces", std::to_string(ec.mesh.num_faces())},
                 {"handle", std::to_string(ec.edit.count(db::Role::Handle))},
                 {"fixed", std::to_string(ec.edit.count(db::Role::Fixed))},
                 {"method", method},
                 {"constraints", db::to_string(o.constraints)},
                 {"build", db::to_string(o.build)},
                 {"backend", s.backend},
                 {"ordering", s.factor.ordering_used},
                 {"n", std::to_string(s.n)},
                 {"nnz", std::to_string(s.nnz)},
                 {"nnz_factor", std::to_string(s.factor.nnz_factor)},
                 {"build_s", db::num(t.build)},
                 {"analyze_s", db::num(t.analyze)},
                 {"factorize_s", db::num(t.factorize)},
                 {"init_s", db::num(t.init())},
                 {"frames", std::to_string(frames)},
                 {"frame_median_s", db::num(median)},
                 {"matrix_bytes", std::to_string(d->matrix_bytes())},
                 {"factor_bytes", std::to_string(d->factor_bytes())},
                 {"process_peak_rss_bytes", std::to_string(db::peak_rss_bytes())}});
        std::cerr << fmt::format("[deform_cases] {:14s} {:3s} n={:6d} init {:.3f} s  frame {:.4f} s\n", label,
                                 method, s.n, t.init(), median);
      }
    }
    csv.write(out);
    std::cerr << "[deform_cases] wrote " << out << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "exp_deform_cases: error: " << e.what() << "\n";
    return db::exit_code(e);
  }
}
