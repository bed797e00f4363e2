#include "harness/shards.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"

namespace db::harness {
namespace fs = std::filesystem;

Shard parse_shard(const std::string& option, const std::string& text) {
  Shard s;
  const std::size_t slash = text.find('/');
  auto whole = [](const std::string& t, int& v) {
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size();
  };
  if (slash == std::string::npos || !whole(text.substr(0, slash), s.index) || !whole(text.substr(slash + 1), s.count) ||
      s.count < 1 || s.count > 10000 || s.index < 1 || s.index > s.count)
    throw UsageError(fmt::format("{} {}: expected I/N with 1 <= I <= N <= 10000 (shard I of N)", option, text));
  return s;
}

void add_shard_options(CLI::App& app, ShardOptions& o) {
  auto* shard = app.add_option("--shard", o.shard,
                               "run shard I of N of the grid (every N-th group of cells of one mesh), writing to "
                               "RESULTS/shards/I-of-N/")
                    ->type_name("I/N")
                    ->check(CLI::Validator(
                        [](std::string& t) {
                          try {
                            parse_shard("--shard", t);
                          } catch (const UsageError& e) {
                            return std::string(e.what());
                          }
                          return std::string();
                        },
                        ""));
  app.add_option("--merge-shards", o.merge,
                 "run nothing: merge the CSVs of RESULTS/shards/1..N-of-N/ into RESULTS/ as one run writes them")
      ->type_name("N")->transform(cli::Integer(1, 10000))->excludes(shard);
}

std::vector<std::size_t> shard_cells(const std::vector<std::string>& groups, const Shard& s) {
  std::vector<std::size_t> cells;
  long long group = -1;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    if (i == 0 || groups[i] != groups[i - 1]) ++group;
    if (!s.active() || group % s.count == s.index - 1) cells.push_back(i);
  }
  return cells;
}

std::string shard_directory(const std::string& results, int index, int count) {
  return (fs::path(results) / "shards" / fmt::format("{}-of-{}", index, count)).string();
}

namespace {

struct ShardFile {
  std::string header;
  std::map<std::string, std::vector<std::string>> lines;  // key -> its lines, in file order
};

ShardFile read_shard(const std::string& path, const std::function<std::string(const CsvRow&)>& key_of) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw InputError(fmt::format("shard merge: cannot read {} (did that shard run?)", path));
  ShardFile f;
  std::vector<std::string> columns;
  f.header = each_csv_line(path, [&](int, const std::string& header, const std::string& line) {
    if (columns.empty()) columns = split_csv_line(header);
    const std::vector<std::string> fields = split_csv_line(line);
    CsvRow row;
    for (std::size_t i = 0; i < fields.size() && i < columns.size(); ++i) row[columns[i]] = fields[i];
    f.lines[key_of(row)].push_back(line);
  });
  return f;
}

}  // namespace

void merge_shard_csv(const std::string& results, int count, const std::string& name, const std::string& out,
                     const std::vector<std::string>& order, const std::function<std::string(const CsvRow&)>& key_of) {
  std::vector<ShardFile> shards;
  for (int i = 1; i <= count; ++i) {
    const std::string path = (fs::path(shard_directory(results, i, count)) / name).string();
    shards.push_back(read_shard(path, key_of));
    if (shards.back().header != shards.front().header)
      throw InputError(fmt::format("shard merge: {} has other columns than shard 1's {}", path, name));
  }
  std::map<std::string, int> owner;
  for (int i = 0; i < count; ++i)
    for (const auto& [key, lines] : shards[std::size_t(i)].lines) {
      if (std::find(order.begin(), order.end(), key) == order.end())
        throw InputError(fmt::format("shard merge: {} of shard {} has rows of '{}', which is no group of this grid "
                                     "(other options than the shards'?)", name, i + 1, key));
      if (!owner.emplace(key, i).second)
        throw InputError(fmt::format("shard merge: rows of '{}' in {} of shards {} and {}", key, name,
                                     owner[key] + 1, i + 1));
    }
  write_atomically(out, [&](std::ostream& o) {
    o << shards.front().header << "\n";
    for (const std::string& key : order)
      if (auto it = owner.find(key); it != owner.end())
        for (const std::string& line : shards[std::size_t(it->second)].lines[key]) o << line << "\n";
  });
}

}  // namespace db::harness
