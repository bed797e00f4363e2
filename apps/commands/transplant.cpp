// deformbench transplant SOURCE TARGET --out FILE: grafting a patch (applications/transplant.h).
#include <memory>

#include "applications/application_measures.h"
#include "commands.h"
#include "core/cli.h"
#include "core/timer.h"
#include "patch_args.h"

namespace db::commands {

Command add_transplant(CLI::App& tool) {
  auto a = std::make_shared<PatchArgs>();
  auto o = std::make_shared<TransplantOptions>();
  CLI::App* app = tool.add_subcommand(
      "transplant", "transplanting: cut a target region out and join a source patch in its place (a zippered "
                    "seam), the LSE solve blending the two surfaces' detail over a transition zone");
  add_patch_options(*app, *a, "the mesh the grafted patch comes from (.off, .ply, .obj)");
  app->add_option("--zone", o->zone, "transition zone width, a fraction of the source patch's parameter radius")
      ->type_name("Z")->check(cli::Real(0.01, 1))->capture_default_str();
  return {app, [app, a, o] {
            const PatchInputs in = load_patch_inputs(*app, *a);
            Timer t;
            const Transplant r = transplant_patch(in.source, in.source_region, in.target, in.target_region, *o);
            const double total = t.seconds();
            write_outputs(*a, "transplant", in, r.solve.system.backend, r.result,
                          transplant_measures(r, in.target, total));
            return 0;
          }};
}

}  // namespace db::commands
