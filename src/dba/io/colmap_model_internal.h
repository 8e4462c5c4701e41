// What the COLMAP text and binary readers and writers share, not for use
// outside io/ (not installed): paths, validation with line numbers, the
// checks before a write. Defined in colmap_model.cc.
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dba/io/colmap_model.h"

namespace dba {
namespace colmap_internal {

// Whether q (w, x, y, z) reads as a rotation: its norm finite and not zero
// (it is normalised). The one check of every quaternion COLMAP's files hold
// (the images', the frames', the sensors'), refused with kNotARotation after
// what names it.
bool IsRotationQuaternion(const std::array<double, 4>& q);
inline constexpr char kNotARotation[] = " is zero or its norm is not finite";

// "<dir>/<name>" (no separator doubled).
std::string JoinPath(const std::string& dir, const std::string& name);

// The line of each entry in its text file (cameras, images: the image's first
// line, points3D), so that validation errors can name it; empty vectors for
// binary files.
struct ColmapSourceLines {
  std::vector<int64_t> cameras;
  std::vector<int64_t> images;
  std::vector<int64_t> points3D;
};

// ValidateColmapModel with line numbers (`lines` may be null).
void ValidateColmapModel(const ColmapModel& model, const std::string& dir,
                         const std::string& extension, const ColmapSourceLines* lines);

// Creates `dir` (and parents) if missing; std::runtime_error on failure.
void EnsureDirectory(const std::string& dir);

// Checks what a writer needs before it writes anything: known camera models
// with the right parameter count, image names free of NUL bytes and, for
// text, non-empty and free of CR, LF and leading/trailing blanks (they would
// not read back). std::invalid_argument otherwise.
void CheckWritable(const ColmapModel& model, bool text);

// COLMAP >= 3.12's rigs and frames beside a model in `dir`, in the model's
// format (COLMAP reads only those), into model->rigs and model->frames,
// each field checked by file and line (byte, for binary files). Defined in
// colmap_rigs.cc.
void ReadRigsAndFrames(const std::string& dir, bool binary, ColmapModel* model);
}  // namespace colmap_internal
}  // namespace dba
