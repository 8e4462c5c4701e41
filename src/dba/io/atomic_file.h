// Writes a whole file atomically: to `path.tmp.<pid>`, fsync, rename over
// `path`. On failure the temporary is removed and std::runtime_error names the
// path and the system error. Thread safety: safe for distinct paths.
#pragma once

#include <string>
#include <string_view>

namespace dba {

void WriteFileAtomically(const std::string& path, std::string_view contents);

}  // namespace dba
