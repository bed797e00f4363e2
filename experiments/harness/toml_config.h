#pragma once
//! The drivers' options files read as strict TOML (toml++, Debian's libtomlplusplus-dev) instead of CLI11's lenient
//! TOML/INI reader, which took an unclosed list as a value built from the next line, accepted a list left open at
//! the end of the file and named no file or line. Every syntax error names the file, the line and the column;
//! a top-level key is an option (`option = value`, a list of scalars for a repeated option); a table, a list of
//! tables or a nested list is refused, and so is a key that is no option. CLI11 still applies the values (the
//! command line wins).
#include <memory>

#include <CLI/CLI.hpp>

namespace db::harness {

//! A CLI11 config formatter over toml++ for `app`'s options; `config` is its --config option, whose value names the
//! file in messages.
//! \throw CLI::ParseError (exit code 1 through cli::run) for a syntax error, a key that is no option of `app`, or a
//! value that is no option value.
std::shared_ptr<CLI::Config> strict_toml_config(const CLI::App& app, const CLI::Option* config);

}  // namespace db::harness
