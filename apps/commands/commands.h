#pragma once
// deformbench's application subcommands (coat, transplant), one file each; apps/deformbench.cpp adds them.
#include <functional>

#include <CLI/CLI.hpp>

namespace db::commands {

//! A subcommand added to the tool and what runs it when it was the one parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

//! `deformbench coat SOURCE TARGET --out FILE ...` (apps/commands/coat.cpp).
Command add_coat(CLI::App& tool);
//! `deformbench transplant SOURCE TARGET --out FILE ...` (apps/commands/transplant.cpp).
Command add_transplant(CLI::App& tool);

}  // namespace db::commands
