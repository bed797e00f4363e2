#pragma once
//! A driver's grid cut into slices for several machines (`--shard I/N`), and the merge of the slices' CSVs into
//! the ones one unsharded run writes (`--merge-shards N`).
//!
//! The grid is a list of cells in a fixed order; consecutive cells of one group (the cells of one mesh: they share
//! the loaded mesh, the reference cell their errors are measured against, measurements reused between tables)
//! always run together. Group g (counted from 0 in grid order) belongs to shard g mod N + 1: a shard's cells are
//! the grid's, in the grid's order, and the shards of one grid never overlap and together cover it. Shard I of N
//! writes its CSVs to RESULTS/shards/I-of-N/; the merge reads them back and writes RESULTS/NAME with the header
//! once and every group's rows in grid order, each line as its shard wrote it.
#include <functional>
#include <string>
#include <vector>

#include "core/cli.h"
#include "harness/csv_reader.h"

namespace db::harness {

struct Shard {
  int index = 0, count = 0;  //!< shard `index` of `count`, 1-based; count 0: the whole grid
  bool active() const { return count > 0; }
};

//! "I/N" with 1 <= I <= N <= 10000. \throw UsageError otherwise (naming `option`).
Shard parse_shard(const std::string& option, const std::string& text);

//! The drivers' shard options: --shard I/N (run that slice) and --merge-shards N (run nothing; merge).
struct ShardOptions {
  std::string shard;
  int merge = 0;
  Shard parsed() const { return shard.empty() ? Shard{} : parse_shard("--shard", shard); }
};
void add_shard_options(CLI::App& app, ShardOptions& o);
//! Which cells of a grid shard `s` runs (indices into the grid, ascending). `groups[i]` is cell i's group; a group
//! is the run of consecutive cells with one key. The whole grid when `s` is not active.
std::vector<std::size_t> shard_cells(const std::vector<std::string>& groups, const Shard& s);
//! The cells of `grid` that shard `s` runs, in grid order; `group_of(cell)` is a cell's group key.
template <class Cell, class GroupOf>
std::vector<Cell> shard_slice(const std::vector<Cell>& grid, const Shard& s, GroupOf group_of) {
  std::vector<std::string> groups;
  for (const Cell& c : grid) groups.push_back(group_of(c));
  std::vector<Cell> mine;
  for (std::size_t i : shard_cells(groups, s)) mine.push_back(grid[i]);
  return mine;
}
//! RESULTS/shards/I-of-N.
std::string shard_directory(const std::string& results, int index, int count);

//! Merges file `name` of every shard directory of RESULTS (1..count) into `out`: the header once, then for each key
//! of `order` the rows whose `key_of(row)` is that key, from the one shard that has them, in that
//! shard's order. \throw InputError for a missing shard file, headers that differ, a key found in two shards or a
//! row whose key is not in `order`.
void merge_shard_csv(const std::string& results, int count, const std::string& name, const std::string& out,
                     const std::vector<std::string>& order, const std::function<std::string(const CsvRow&)>& key_of);

}  // namespace db::harness
