// COLMAP sparse models in COLMAP's text form: cameras.txt, images.txt and
// points3D.txt in one directory.
//
//   cameras.txt   # comment lines, then per camera one line
//                 CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]
//   images.txt    per image two lines: the first
//                 IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME
//                 the second (possibly empty) X Y POINT3D_ID ... (-1: none)
//   points3D.txt  per point one line
//                 POINT3D_ID X Y Z R G B ERROR IMAGE_ID POINT2D_IDX ...
//
// Reading: lines starting with '#' and empty lines are skipped (except the
// POINTS2D line after an image line, which is taken as it is, like COLMAP
// does); tokens are separated by blanks; CRLF line ends are accepted. The NAME
// is the rest of the image line after CAMERA_ID, trimmed. Numbers must parse
// completely and be finite.
//
// Writing reproduces COLMAP's writer: the same header comments (with the
// counts and means), one space between tokens, '\n' line ends, entries in
// model order. Doubles are printed in the shortest form that reads back to the
// same bits (std::to_chars), so read -> write -> read is exact (COLMAP prints
// 17 significant digits instead, and normalises the quaternion; here qvec is
// written as held). Each file is written to a temporary and renamed into place.
//
// Thread safety: as colmap_model.h.
#pragma once

#include <string>

#include "dba/io/colmap_model.h"

namespace dba {

// Reads <dir>/cameras.txt, images.txt and points3D.txt and validates the
// model (ValidateColmapModel). Throws dba::InputError with file:line and what
// was expected on malformed input.
ColmapModel ReadColmapText(const std::string& dir);

// Writes the three text files into `dir` (created if missing), replacing any
// existing ones. std::invalid_argument if the model cannot be written
// (colmap_internal::CheckWritable), std::runtime_error on I/O failure.
void WriteColmapText(const ColmapModel& model, const std::string& dir);

}  // namespace dba
