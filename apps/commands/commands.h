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
//! deform's options table (methods/deform_options.h) on a subcommand, but the keys in `skip`; each given value
//! lands in values[key] ("1" for a switch) (apps/commands/deform.cpp).
void add_deform_option_table(CLI::App& d, std::map<std::string, std::string>& values,
                             const std::vector<std::string>& skip = {});
//! `deformbench coat SOURCE TARGET --out FILE ...` (apps/commands/coat.cpp).
Command add_coat(CLI::App& tool);
//! `deformbench transplant SOURCE TARGET --out FILE ...` (apps/commands/transplant.cpp).
Command add_transplant(CLI::App& tool);

}  // namespace db::commands
