#pragma once
//! Outputs are written to "<path>.tmp.<pid>" and renamed into place, so a failure never leaves a partial file.
#include <functional>
#include <ostream>
#include <string>

namespace db {

//! Calls write(stream) on a temporary file next to path, then renames it to path.
//! \throw Error when the file cannot be opened, written or renamed (the temporary is removed).
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                      bool binary = false);

}  // namespace db
