// Writing of BAL problem files (the format read by bal_reader.h).
#pragma once

#include <string>

#include "dba/problem/problem.h"

namespace dba {

// Writes `problem` as BAL text to `path`: observations in point-major order,
// every value in the shortest form that reads back to the same double, so
// ReadBal(path) reproduces the arrays bit for bit. When `path` ends in ".bz2"
// the text is bzip2-compressed.
//
// The file is written to `path + ".tmp.<pid>.<n>"` and renamed over `path`, so a
// reader never sees a half-written file. On any failure (cannot create, disk
// full, write/close/rename error) the temporary is removed and
// std::runtime_error is thrown naming the path and the system error.
// Throws std::invalid_argument for inconsistent arrays or non-finite values,
// and for a photogrammetric problem (CameraModel::kPhoto: the BAL format has
// no intrinsics shared by several images; write .dba), before creating any
// file. The fixed flags are not written (BAL has no place for them).
void WriteBal(const Problem& problem, const std::string& path);

}  // namespace dba
