#include "solvers/base/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "solvers/base/error.h"

namespace db {

namespace fs = std::filesystem;

namespace {

// ".tmp.PID": what a temporary of this process adds to its target's name.
std::string temporary_suffix() { return ".tmp." + std::to_string(::getpid()); }

// A StagedOutputs temporary ("DIR/NAME.tmp.PID.EXT") is already one: it is written as it is, and named by its
// target in messages.
bool is_staged(const fs::path& p) {
  const std::string stem = p.stem().string(), suffix = temporary_suffix();
  return stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string target_of(const fs::path& p) {
  if (!is_staged(p)) return p.string();
  const std::string stem = p.stem().string();
  return (p.parent_path() / (stem.substr(0, stem.size() - temporary_suffix().size()) + p.extension().string()))
      .string();
}

// "cannot write PATH: No space left on device", with errno as the failed call left it.
[[noreturn]] void write_failed(const fs::path& p) {
  const int err = errno;
  throw Error("cannot write " + target_of(p) + ": " + (err != 0 ? std::strerror(err) : "write failed"));
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const fs::path target(path);
  if (target.has_parent_path() && !fs::exists(target.parent_path()))
    throw Error("output directory does not exist: " + target.parent_path().string());
  const std::string tmp = is_staged(target) ? path : path + temporary_suffix();
  const cleanup::ScratchPath on_signal(tmp);
  try {
    {
      errno = 0;
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::out : std::ios::out);
      if (!out) write_failed(target);
      write(out);
      out.flush();
      if (!out) write_failed(target);
      out.close();
      if (!out) write_failed(target);
    }
    std::error_code ec;
    if (tmp != path) fs::rename(tmp, target, ec);
    if (ec) throw Error("cannot write " + path + ": " + ec.message());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

StagedOutputs::~StagedOutputs() {
  std::error_code ec;
  for (const Entry& e : entries_) fs::remove(e.temporary, ec);
}

std::string StagedOutputs::stage(const std::string& target) {
  for (const Entry& e : entries_)
    if (same_file(e.target, target)) throw Error("two outputs name the same file: " + e.target + " and " + target);
  const fs::path p(target);
  const fs::path tmp = p.parent_path() / (p.stem().string() + temporary_suffix() + p.extension().string());
  entries_.push_back({target, tmp.string(), cleanup::ScratchPath(tmp.string())});
  return tmp.string();
}

namespace {

// Keeps the file at `target` (if any) under a second name beside it ("DIR/NAME.tmp.PID.kept.EXT", a name of this
// process's temporaries, as the staged ones are) until the commit is done: a hard link, so the target stays in place; where links are refused, the target is renamed away. Returns
// the second name, "" when there is no earlier file. \throw Error when it cannot be kept.
std::string keep_earlier(const std::string& target) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target, ec);
  if (!fs::exists(st) || fs::is_directory(st)) return "";  // a directory is not replaced: the rename fails
  const fs::path p(target);
  const std::string kept =
      (p.parent_path() / (p.stem().string() + temporary_suffix() + ".kept" + p.extension().string())).string();
  fs::remove(kept, ec);
  if (::link(target.c_str(), kept.c_str()) == 0 || ::rename(target.c_str(), kept.c_str()) == 0) return kept;
  throw Error("cannot write " + target + ": " + std::strerror(errno) + " (its earlier version could not be kept)");
}

}  // namespace

void StagedOutputs::roll_back(std::size_t committed, const std::vector<std::string>& kept) {
  std::error_code ec;
  for (std::size_t j = 0; j < committed; ++j) {
    if (kept[j].empty()) fs::remove(entries_[j].target, ec);
    else fs::rename(kept[j], entries_[j].target, ec);
  }
  // The target that failed: renamed away (no hard links) but not replaced.
  if (committed < kept.size() && !kept[committed].empty() && !fs::exists(entries_[committed].target, ec))
    fs::rename(kept[committed], entries_[committed].target, ec);
  for (const std::string& k : kept)
    if (!k.empty()) fs::remove(k, ec);
}

void StagedOutputs::commit() {
  const cleanup::DeferSignals whole;  // an interrupt waits until every output is in place, or put back
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::error_code ec;
    try {
      kept.push_back(keep_earlier(entries_[i].target));
    } catch (...) {
      roll_back(i, kept);
      throw;
    }
    fs::rename(entries_[i].temporary, entries_[i].target, ec);
    if (!ec) continue;
    roll_back(i, kept);
    throw Error("cannot write " + entries_[i].target + ": " + ec.message() +
                (i > 0 ? " (the outputs written before it were put back as they were)" : ""));
  }
  std::error_code ignored;
  for (const std::string& k : kept)
    if (!k.empty()) fs::remove(k, ignored);
  entries_.clear();
}

}  // namespace db
