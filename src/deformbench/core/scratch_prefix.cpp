#include "core/scratch_prefix.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include <fmt/format.h>

namespace db {

namespace fs = std::filesystem;

ScratchPrefix::ScratchPrefix(const std::string& name)
    : prefix_((fs::temp_directory_path() / fmt::format("deformbench-{}-{}-", name, ::getpid())).string()),
      on_signal_(prefix_, cleanup::ScratchPath::Prefix) {}

ScratchPrefix::~ScratchPrefix() {
  const fs::path dir = fs::path(prefix_).parent_path();
  const std::string leaf = fs::path(prefix_).filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().rfind(leaf, 0) == 0) fs::remove(it->path(), ec);
}

}  // namespace db
