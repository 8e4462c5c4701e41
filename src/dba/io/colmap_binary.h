// COLMAP sparse models in COLMAP's binary form: cameras.bin, images.bin and
// points3D.bin in one directory. All numbers little-endian, no padding:
//
//   cameras.bin   u64 num_cameras, then per camera
//                 u32 camera_id, i32 model_id, u64 width, u64 height,
//                 f64 params[number of the model's parameters]
//   images.bin    u64 num_images, then per image
//                 u32 image_id, f64 qw qx qy qz, f64 tx ty tz, u32 camera_id,
//                 name bytes + '\0', u64 num_points2D,
//                 (f64 x, f64 y, u64 point3D_id) x num_points2D
//                 (point3D_id 2^64-1 = no 3D point)
//   points3D.bin  u64 num_points, then per point
//                 u64 point3D_id, f64 x y z, u8 r g b, f64 error,
//                 u64 track_length, (u32 image_id, u32 point2D_idx) x length
//
// Read -> write gives the same bytes (entries in file order, values bit for
// bit). Files are streamed, never held whole in memory; each output file is
// written to a temporary and renamed into place.
//
// Thread safety: as colmap_model.h.
#pragma once

#include <string>

#include "dba/io/colmap_model.h"

namespace dba {

// Reads <dir>/cameras.bin, images.bin and points3D.bin and validates the model
// (ValidateColmapModel). Throws dba::InputError (line 0, the byte offset in
// the message) on truncated files, unknown camera model ids, counts larger
// than the file, trailing bytes, non-finite values, or inconsistencies.
ColmapModel ReadColmapBinary(const std::string& dir);

// Writes the three binary files into `dir` (created if missing), replacing
// any existing ones. std::invalid_argument if the model cannot be written
// (colmap_internal::CheckWritable), std::runtime_error on I/O failure.
void WriteColmapBinary(const ColmapModel& model, const std::string& dir);

}  // namespace dba
