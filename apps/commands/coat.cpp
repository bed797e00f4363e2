// deformbench coat SOURCE TARGET --out FILE: coating transfer (applications/coating_transfer.h).
#include <memory>

#include "applications/application_measures.h"
#include "commands.h"
#include "core/cli.h"
#include "core/timer.h"
#include "patch_args.h"

namespace db::commands {

Command add_coat(CLI::App& tool) {
  auto a = std::make_shared<PatchArgs>();
  auto o = std::make_shared<CoatingOptions>();
  CLI::App* app = tool.add_subcommand(
      "coat", "coating transfer: the detail of a source patch (its surface minus its smoothed version) onto a "
              "target patch, reconstructed by the LSE solve");
  add_patch_options(*app, *a, "the mesh whose coating is transferred (.off, .ply, .obj)");
  app->add_option("--smooth-weight", o->smooth_weight,
                  "w of the source's smoothing: smaller takes broader detail into the coating")
      ->type_name("W")->check(cli::Real(1e-6, 1e3))->capture_default_str();
  app->add_option("--amplitude", o->amplitude, "multiplies the transferred detail (negative: engraved, not embossed)")
      ->type_name("A")->check(cli::Real(-1e3, 1e3))->capture_default_str();
  auto map = std::make_shared<std::string>(to_string(o->map));
  auto encoding = std::make_shared<std::string>(to_string(o->encoding));
  app->add_option("--map", *map, "the patches' maps onto the disk: " + enum_choices<DiskMap>())
      ->type_name("MAP")->check(CLI::IsMember(enum_names<DiskMap>()))->capture_default_str();
  app->add_option("--encoding", *encoding,
                  "the detail: height (displacement from the smooth surface) or laplacian (Laplacian coordinates)")
      ->type_name("E")->check(CLI::IsMember(enum_names<DetailEncoding>()))->capture_default_str();
  return {app, [app, a, o, map, encoding] {
            o->map = parse_enum<DiskMap>(*map);
            o->encoding = parse_enum<DetailEncoding>(*encoding);
            const PatchInputs in = load_patch_inputs(*app, *a);
            Timer t;
            const Coating c = extract_coating(in.source, in.source_region, *o);
            const CoatedTarget r = transfer_coating(c, in.target, in.target_region, *o);
            const double total = t.seconds();
            write_outputs(*a, "coat", in, r.solve.system.backend, r.result,
                          coat_measures(c, r, in.target, total));
            return 0;
          }};
}

}  // namespace db::commands
