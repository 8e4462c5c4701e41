// What an input path holds, decided once, by its content and not its name:
// a COLMAP sparse model directory (text or binary), a dba binary problem
// (its magic) or BAL text, plain or bzip2 (the BAL reader tells which).
// `dba solve`, `dba convert`, `dba info` and Python decide it here, once per
// run, and ask the source afterwards, never the path again; and they read a
// problem of any kind here (ReadInputProblem).
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <string>

#include "dba/io/colmap_model.h"
#include "dba/problem/fixings.h"
#include "dba/problem/problem.h"

namespace dba {

enum class InputKind { kBalText, kBinary, kColmap };

struct InputSource {
  std::string path;
  InputKind kind = InputKind::kBalText;
  ColmapFormat colmap_format = ColmapFormat::kBinary;  // kColmap: the model's files

  bool colmap() const { return kind == InputKind::kColmap; }
  bool binary() const { return kind == InputKind::kBinary; }
  // "COLMAP model", "dba binary" or "BAL text".
  const char* KindName() const;
};

// A directory holding a COLMAP model is one; a regular file that starts
// with the .dba magic is a binary problem; anything else is BAL text (its
// reader refuses what is not, naming the file). Does not throw.
InputSource DecideInput(const std::string& path);

// The problem `source` holds (COLMAP: one intrinsic group per COLMAP
// camera), `fixings` applied (the intrinsics' names checked against the
// groups' models) and rig images composed from their frames. Throws
// InputError for bad input, std::invalid_argument for fixings that do not
// fit.
Problem ReadInputProblem(const InputSource& source, const Fixings& fixings);

// What a problem read with nothing asked holds fixed: the principal points
// (photogrammetric practice without a calibration target; COLMAP's
// refine_principal_point 0).
Fixings DefaultFixings();

}  // namespace dba
