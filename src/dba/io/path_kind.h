// What a problem file's name says it holds, the one place that reads
// extensions: .dba the binary format (io/binary_problem.h), .bz2 BAL text
// compressed, .txt BAL text, anything else none of these (a COLMAP model
// directory, for an output). Readers detect the kind by content; writers
// and the checks of outputs go by this.
// Thread safety: pure.
#pragma once

#include <string_view>

namespace dba {

enum class PathKind { kBinary, kBalBz2, kBalText, kOther };

inline PathKind KindOfPath(std::string_view path) {
  if (path.ends_with(".dba")) return PathKind::kBinary;
  if (path.ends_with(".bz2")) return PathKind::kBalBz2;
  if (path.ends_with(".txt")) return PathKind::kBalText;
  return PathKind::kOther;
}

}  // namespace dba
