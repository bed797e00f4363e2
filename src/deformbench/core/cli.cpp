#include "core/cli.h"

#include <fcntl.h>
#include <linux/fs.h>
#include <linux/magic.h>
#include <sys/ioctl.h>
#include <sys/statfs.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <new>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"

namespace db::cli {
namespace {

namespace fs = std::filesystem;

bool is_whole_number(const std::string& s) {
  std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  if (i == s.size()) return false;
  for (; i < s.size(); ++i)
    if (s[i] < '0' || s[i] > '9') return false;
  return true;
}

// The decimal digits of a whole number written plainly ("-12") or in scientific notation ("1e3", "2.5E2"), with
// its sign; "" when s is no whole number ("2.5", "1e-1", "nan", "0x10").
std::string whole_number_digits(const std::string& s) {
  const std::size_t e = s.find_first_of("eE");
  std::string mantissa = s.substr(0, e);
  long long exponent = 0;
  if (e != std::string::npos) {
    const std::string x = s.substr(e + 1);
    if (!is_whole_number(x) || x.size() > 6) return {};
    exponent = std::stoll(x);
  }
  const std::size_t dot = mantissa.find('.');
  if (dot != std::string::npos) {
    exponent -= static_cast<long long>(mantissa.size() - dot - 1);
    mantissa.erase(dot, 1);
    if (dot == 0 || mantissa.size() == dot) return {};  // ".5", "5."
  }
  if (!is_whole_number(mantissa)) return {};
  for (; exponent < 0; ++exponent) {
    if (mantissa.back() != '0' || mantissa.size() < 2) return {};
    mantissa.pop_back();
  }
  if (!is_whole_number(mantissa)) return {};  // "-0e-1" left only the sign
  if (exponent > 30) return mantissa + std::string(30, '0');  // out of every range; strtoll says so
  return mantissa + std::string(static_cast<std::size_t>(exponent), '0');
}

// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

void collect_names(const CLI::App& app, std::vector<std::string>& names) {
  for (const CLI::Option* o : app.get_options())
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
  for (const CLI::App* sub : app.get_subcommands({})) collect_names(*sub, names);
}

// "unknown option --frame (did you mean --frames?)" for every extra that looks like an option.
std::string describe_extras(const CLI::App& app, const std::vector<std::string>& extras) {
  std::vector<std::string> names;
  collect_names(app, names);
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < extras.size(); ++i) {
    const std::string& x = extras[i];
    if (x.rfind("-", 0) != 0) {
      parts.push_back(fmt::format("unexpected argument '{}'", x));
      continue;
    }
    const std::string key = x.substr(0, x.find('='));
    std::string best;
    std::size_t best_d = 3;  // suggest only close misspellings
    for (const std::string& n : names) {
      const std::size_t d = edit_distance(key, n);
      if (d < best_d) best_d = d, best = n;
    }
    parts.push_back(best.empty() ? fmt::format("unknown option {}", key)
                                 : fmt::format("unknown option {} (did you mean {}?)", key, best));
    // The unknown option's value, if it had one, is no separate mistake.
    if (x.find('=') == std::string::npos && i + 1 < extras.size() && extras[i + 1].rfind("-", 0) != 0) ++i;
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

const CLI::App& innermost(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands())
    if (sub->parsed()) return innermost(*sub);
  return app;
}

// "unknown command 'bogus' (commands: deform, solvers)" when a tool with subcommands got a word that is none of
// them; "" otherwise.
std::string unknown_subcommand(const CLI::App& app) {
  const auto subs = app.get_subcommands({});
  if (subs.empty() || !app.get_subcommands().empty() || app.remaining().empty()) return {};
  const std::string word = app.remaining().front();
  if (word.rfind("-", 0) == 0) return {};
  std::vector<std::string> names;
  for (const CLI::App* s : subs) names.push_back(s->get_name());
  return fmt::format("unknown command '{}' (commands: {})", word, fmt::join(names, ", "));
}

// The file's attributes (chattr: FS_APPEND_FL, FS_IMMUTABLE_FL, ...); 0 where it cannot be opened or its file
// system keeps none.
int inode_flags(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return 0;
  int flags = 0;  // the kernel writes an int, whatever the ioctl's declared type
  if (::ioctl(fd, FS_IOC_GETFLAGS, &flags) != 0) flags = 0;
  ::close(fd);
  return flags;
}

// "proc", "sysfs": a kernel file system whose directories take no new files, though access() may say they do.
const char* virtual_file_system(const std::string& dir) {
  struct statfs st {};
  if (::statfs(dir.c_str(), &st) != 0) return nullptr;
  if (st.f_type == PROC_SUPER_MAGIC) return "proc";
  if (st.f_type == SYSFS_MAGIC) return "sysfs";
  return nullptr;
}

}  // namespace

CLI::Validator Integer(long long min, long long max) {
  return CLI::Validator(
      [min, max](std::string& s) -> std::string {
        const std::string digits = whole_number_digits(s);
        if (digits.empty()) return fmt::format("{} is not a whole number", s);
        errno = 0;
        const long long v = std::strtoll(digits.c_str(), nullptr, 10);
        if (errno == ERANGE || v < min || v > max) return fmt::format("{} is outside [{}, {}]", s, min, max);
        s = digits;  // what the option converts (a transform; with check() the value stays as given)
        return {};
      },
      fmt::format("[{}, {}]", min, max));
}

CLI::Validator Real(double min, double max) {
  return CLI::Validator(
      [min, max](std::string& s) -> std::string {
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || s.find_first_of("xXpP") != std::string::npos)
          return fmt::format("{} is not a number", s);
        if (!std::isfinite(v) || errno == ERANGE) return fmt::format("{} is not a finite number", s);
        if (v < min || v > max) return fmt::format("{} is outside [{:g}, {:g}]", s, min, max);
        return {};
      },
      fmt::format("[{:g}, {:g}]", min, max));
}

CLI::Validator OneOf(const std::vector<std::string>& values) {
  return CLI::Validator(
      [values](std::string& s) -> std::string {
        if (std::find(values.begin(), values.end(), s) != values.end()) return {};
        return fmt::format("'{}' is not one of: {}", s, fmt::join(values, ", "));
      },
      fmt::format("{{{}}}", fmt::join(values, "|")));
}

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  const std::string tool = fs::path(argc > 0 ? argv[0] : app.get_name()).filename().string();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << innermost(app).help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ExtrasError&) {
    std::cerr << tool << ": error: " << describe_extras(innermost(app), innermost(app).remaining()) << " (see "
              << tool << " --help)\n";
    return 1;
  } catch (const CLI::ParseError& e) {
    std::cerr << tool << ": error: " << (unknown_subcommand(app).empty() ? e.what() : unknown_subcommand(app))
              << " (see " << tool << " --help)\n";
    return 1;
  }
  try {
    return body();
  } catch (const std::bad_alloc&) {
    std::cerr << tool << ": error: out of memory\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return exit_code(e);
  }
}

void check_directory(const std::string& option, const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UsageError(fmt::format("{}: '{}' is not a directory", option, dir));
  if (!fs::is_directory(dir, ec)) throw UsageError(fmt::format("{}: directory '{}' does not exist", option, dir));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw UsageError(fmt::format("{}: directory '{}' is not writable ({})", option, dir, std::strerror(errno)));
  if (const char* kind = virtual_file_system(dir))
    throw UsageError(fmt::format("{}: directory '{}' is on the kernel's {} file system: no file can be written there",
                                 option, dir, kind));
  // An append-only directory (chattr +a) takes new files but not the rename that puts an output in place.
  if (inode_flags(dir) & FS_APPEND_FL)
    throw UsageError(fmt::format("{}: directory '{}' is append-only (chattr +a): an output cannot be put in place",
                                 option, dir));
  // A full file system is found before the solve, not when the result is written.
  struct statvfs st {};
  if (::statvfs(dir.c_str(), &st) == 0 && st.f_blocks > 0 && st.f_bavail == 0)
    throw UsageError(fmt::format("{}: directory '{}' is full ({})", option, dir, std::strerror(ENOSPC)));
}

void check_output(const std::string& option, const std::string& path, const std::vector<std::string>& extensions,
                  const std::vector<std::string>& inputs) {
  if (path.empty()) throw UsageError(fmt::format("{}: empty path", option));
  const fs::path p(path);
  if (!extensions.empty()) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end())
      throw UsageError(fmt::format("{} {}: unsupported extension '{}' (supported: {})", option, path, ext,
                                   fmt::join(extensions, ", ")));
  }
  check_directory(fmt::format("{} {}", option, path), p.has_parent_path() ? p.parent_path().string() : ".");
  std::error_code ec;
  if (fs::is_directory(p, ec)) throw UsageError(fmt::format("{} {}: is a directory", option, path));
  // An immutable or append-only file (chattr +i / +a) cannot be replaced, though its directory is writable.
  if (fs::exists(p, ec) && ((::access(path.c_str(), W_OK) != 0 && errno == EPERM) ||
                             (inode_flags(path) & (FS_APPEND_FL | FS_IMMUTABLE_FL))))
    throw UsageError(fmt::format("{} {}: cannot be replaced ({}: immutable or append-only)", option, path,
                                 std::strerror(EPERM)));
  for (const std::string& in : inputs)
    if (same_file(path, in))
      throw UsageError(fmt::format("{} {}: is an input file; write the result elsewhere", option, path));
}

}  // namespace db::cli
