#pragma once
// deformbench's subcommands that do work (deform, coat, transplant), one file each; apps/deformbench.cpp adds them.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace db::commands {

//! A subcommand added to the tool and what runs it when it was the one parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

//! `deformbench deform EDIT --out FILE ...` (apps/commands/deform.cpp).
Command add_deform(CLI::App& tool);
//! `deformbench deform-options`: the deform options' table as Markdown (apps/commands/deform.cpp).
Command add_deform_options_listing(CLI::App& tool);
//! `deformbench advise EDIT ...`: every applicable backend on one edit, ranked, with a verdict
//! (apps/commands/advise.cpp).
Command add_advise(CLI::App& tool);
//! `deformbench coat SOURCE TARGET --out FILE ...` (apps/commands/coat.cpp).
Command add_coat(CLI::App& tool);
//! `deformbench transplant SOURCE TARGET --out FILE ...` (apps/commands/transplant.cpp).
Command add_transplant(CLI::App& tool);
//! `deformbench export-system EDIT --out A.mtx ...` (apps/commands/export_system.cpp).
Command add_export_system(CLI::App& tool);

}  // namespace db::commands
