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

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const fs::path target(path);
  if (target.has_parent_path() && !fs::exists(target.parent_path()))
    throw Error("output directory does not exist: " + target.parent_path().string());
  const std::string tmp = is_staged(target) ? path : path + temporary_suffix();
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
  const fs::path p(target);
  const fs::path tmp = p.parent_path() / (p.stem().string() + temporary_suffix() + p.extension().string());
  entries_.push_back({target, tmp.string()});
  return tmp.string();
}

void StagedOutputs::commit() {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::error_code ec;
    fs::rename(entries_[i].temporary, entries_[i].target, ec);
    if (!ec) continue;
    std::error_code ignored;
    for (std::size_t j = 0; j < i; ++j) fs::remove(entries_[j].target, ignored);
    throw Error("cannot write " + entries_[i].target + ": " + ec.message() +
                (i > 0 ? " (the outputs written before it were removed again)" : ""));
  }
  entries_.clear();
}

}  // namespace db
