#include "core/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace db {

namespace fs = std::filesystem;

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  const fs::path target(path);
  if (target.has_parent_path() && !fs::exists(target.parent_path()))
    throw Error("output directory does not exist: " + target.parent_path().string());
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::out : std::ios::out);
      if (!out) throw Error("cannot open for writing: " + tmp);
      write(out);
      out.flush();
      if (!out) throw Error("write failed: " + tmp);
    }
    fs::rename(tmp, target);
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
  const fs::path tmp =
      p.parent_path() / (p.stem().string() + ".tmp." + std::to_string(::getpid()) + p.extension().string());
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
