// The dba binary problem format: a versioned, mmap/pread-friendly layout of
// a Problem, observations point-major, so a rank can read the points it
// owns without reading the rest (docs/design.md §4, §6).
//
// Version 1 holds BAL problems; version 2 adds the photogrammetric model
// (poses plus shared intrinsic groups of 5 RADIAL parameters) and the fixed
// flags; version 3 gives each group a lens model (problem/lens_model.h) and
// the groups 1 to 16 parameter slots. A writer uses the lowest version that
// holds the problem (version 2: camera model 2 or fixed flags; version 3: a
// group whose model is not RADIAL, or slots other than 5), so older problems
// are still written byte for byte as before; all versions are read.
//
// Version 4 (rigs, problem.h) is version 3 with a 16-byte extension of the
// header (u64 frames, u64 rig section offset; the cameras start at 144),
// f64[6 · frames] rig_from_world then f64[6 · groups] sensor_from_rig right
// after the intrinsics (so the three are Problem::cameras), and a rig
// section after the image groups: i32[cameras] each image's frame, then
// u8[groups] each group's SensorKind, zero-padded to 8 bytes. Written only
// for a problem with rigs.
//
//   offset 0    header, 128 bytes:
//                 magic "DBAPROB\n" | u32 version (1 or 2) | u32 byte-order
//                 mark 0x01020304 | u32 camera model (1 = BAL, 9 parameters
//                 per camera; 2 = photogrammetric, 6 per image, version 2
//                 only) | u32 camera size (9 or 6) | u64 cameras (images) |
//                 u64 points | u64 observations | u64 section offsets:
//                 cameras, points, point offsets, observation cameras,
//                 observation pixels | u64 file size |
//               version 1: zero padding (32 bytes; written as zeros, not
//                 read)
//               version 2: u32 intrinsic groups (model 1: 0; model 2: 1 to
//                 cameras, which are at most 2^31) | u16 optional sections (bit 0: fixed cameras,
//                 bit 1: free intrinsics, model 2 only; other bits 0) | u16 zero | u64
//                 section offsets: intrinsics, image groups, flags
//               version 3 (model 2 only): as version 2, but the u16 after
//                 the optional sections is the slots per group S (1 to 16)
//   sections, each starting at a multiple of 8 bytes, in this order:
//     cameras        f64[camera size · cameras]  BAL cameras, or image poses
//                                          (ω, t; world -> camera, COLMAP's
//                                          axes, camera/photo_camera.h)
//     intrinsics     f64[5 · groups]     (version 2) f, cx, cy, k1, k2 per
//                                          group; version 3: f64[S · groups],
//                                          each group's model's parameters in
//                                          its order, unused slots 0; right
//                                          after the cameras, so the two are
//                                          Problem::cameras
//     group models   (version 3) u8[2 · groups]  per group its lens model id
//                                          and parameter count (checked
//                                          against the model), zero-padded
//                                          to 8 bytes; its offset follows
//                                          from the counts (not in the header)
//     image groups   i32[cameras]        (version 2, model 2; else empty)
//                                          group of each image, in
//                                          [0, groups); zero-padded to 8 bytes
//     flags          (version 2) u8[cameras] fixed_cameras (0/1) if bit 0,
//                                          then u8[groups] free intrinsics
//                                          (version 3: u16[groups]; bit j:
//                                          parameter j, within the group's
//                                          model; the complement of
//                                          fixed_intrinsics) if bit 1;
//                                          zero-padded to 8 bytes
//     points         f64[3 · points]
//     point offsets  i64[points + 1]     observations of point k are
//                                          [offsets[k], offsets[k+1])
//     obs cameras    i32[observations]   (zero-padded to 8 bytes)
//     obs pixels     f64[2 · observations]
// A version-1 file is the same with the three version-2 sections empty.
// All numbers little-endian. Counts are 64-bit; every section offset is fixed
// by the counts and optional bits, and a file whose table or size differs is
// refused.
//
// The fixed flags are problem data, stored when non-empty: fixed_intrinsics
// holds what the problem was posed with fixed (a version-2 file of a COLMAP
// SIMPLE_PINHOLE camera holds it with k1, k2 fixed at 0), and
// fixed_cameras (e.g. a COLMAP model's fixed images) fixes the gauge the
// problem was posed with. A distributed solve needs them on every rank and on
// the main rank alike, which reading them from the one file guarantees.
// Emptiness round-trips: an empty vector writes no flags and reads back empty.
//
// Thread safety: functions are independent; concurrent reads of one file are
// safe.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dba/io/atomic_output_file.h"
#include "dba/problem/problem.h"

namespace dba {

struct BinaryProblemHeader {
  uint32_t version = 0;
  uint32_t camera_model = 0;  // as stored: 1 = BAL, 2 = photogrammetric
  uint32_t camera_size = 0;   // 9 or 6
  CameraModel model = CameraModel::kBal;
  int64_t num_cameras = 0;    // images
  int64_t num_intrinsics = 0; // intrinsic groups (0 for BAL)
  int64_t num_points = 0;
  int64_t num_observations = 0;
  bool has_fixed_cameras = false;
  bool has_intrinsics_free = false;
  int64_t cameras_offset = 0;
  int64_t intrinsics_offset = 0;
  int64_t group_models_offset = 0;  // version 3 (derived, not in the header)
  int64_t image_groups_offset = 0;
  int64_t flags_offset = 0;
  int64_t points_offset = 0;
  int64_t point_offsets_offset = 0;
  int64_t obs_camera_offset = 0;
  int64_t obs_pixel_offset = 0;
  int64_t file_size = 0;
  int32_t intrinsics_size = kPhotoIntrinsicsSize;  // slots per group (version 3: 1 to 16)
  int64_t num_frames = -1;  // version 4 (rigs): frames; else -1
  int64_t rig_offset = 0;   // version 4: image frames, then sensor kinds

  // Size of Problem::cameras: camera size · cameras + slots · groups (and
  // with rigs 6 · (frames + groups)).
  int64_t camera_side_size() const {
    return int64_t{camera_size} * num_cameras + int64_t{intrinsics_size} * num_intrinsics +
           (num_frames >= 0 ? kPhotoPoseSize * (num_frames + num_intrinsics) : 0);
  }
};

// True if the file is a regular file that starts with the binary magic.
bool IsBinaryProblem(const std::string& path);

// Reads and checks the header against the file: magic, version, byte order,
// camera model, intrinsic group count, section layout and file size. Throws
// InputError.
BinaryProblemHeader ReadBinaryProblemHeader(const std::string& path);

// The whole problem. Throws InputError on any inconsistency (offsets not
// monotonic, camera or group ids out of range, non-finite values, flags out
// of range).
Problem ReadBinaryProblem(const std::string& path);

// Visits the visibility graph in chunks of whole points without holding it:
// fn(first_point, offsets (global observation indices, size n + 1),
//    cameras of observations offsets[0] .. offsets[n]).
void ForEachVisibilityChunk(
    const std::string& path, int64_t max_observations_per_chunk,
    const std::function<void(int64_t first_point, std::span<const int64_t> offsets,
                             std::span<const int32_t> cameras)>& fn);

// The same, with the observed pixels of the chunk (2 per observation) when
// `with_pixels` (else an empty span).
void ForEachObservationChunk(
    const std::string& path, int64_t max_observations_per_chunk, bool with_pixels,
    const std::function<void(int64_t first_point, std::span<const int64_t> offsets,
                             std::span<const int32_t> cameras,
                             std::span<const double> pixels)>& fn);

// Points with point_group[k] == group, their observations and the whole
// camera side (all cameras and intrinsic groups, camera_intrinsics, fixed
// flags, model; global ids; see KeepTouchedCameras for the local
// renumbering), read in chunks. `global_point` receives the global id of
// each point read.
Problem ReadBinaryPoints(const std::string& path, std::span<const int32_t> point_group,
                            int32_t group, std::vector<int64_t>* global_point);

// The camera side only: model, cameras (cameras or poses, then
// intrinsics), camera_intrinsics and the fixed flags.
CameraSide ReadBinaryCameraSide(const std::string& path);

// Only the point coordinates (3 per point).
std::vector<double> ReadBinaryPointCoordinates(const std::string& path);

// Writes `problem` to path.tmp.<pid>.<n>, then renames it over `path`.
void WriteBinaryProblem(const Problem& problem, const std::string& path);

// Writes `output` as a copy of the binary problem `input` with its
// camera-side vector (Problem::cameras) and point coordinates replaced,
// streaming the observations through a buffer (they are never all in
// memory). `camera_side` gives the model, the camera-side parameters, the
// image groups and the fixed flags to write (e.g. what a solve ended with and
// held fixed); its counts and image groups must be the input's. Atomic like
// WriteBinaryProblem.
void WriteBinaryWithNewParameters(const std::string& input, const std::string& output,
                                  const Problem& camera_side,
                                  const std::vector<double>& points);

// Streams a problem into the binary format when the counts are known ahead:
// the camera side once, then points one by one in order with their
// observations. Everything goes to path.tmp.<pid>.<n>; Commit() checks that the
// counts were met, syncs and renames; a writer destroyed without Commit()
// removes the temporary. Memory: a buffer of a few MiB (plus the flags).
class BinaryProblemWriter {
 public:
  // A BAL problem (version 1); give the cameras with WriteCameras.
  BinaryProblemWriter(const std::string& path, int64_t num_cameras, int64_t num_points,
                      int64_t num_observations);
  // Any problem: `camera_side` gives the model, the cameras (the whole
  // camera-side vector), camera_intrinsics (the group of each image, kPhoto)
  // and the fixed flags, all written now (its points and observations are
  // ignored). WriteCameras may replace the camera-side values later. Throws
  // std::invalid_argument when they are inconsistent (sizes, group ids out
  // of range, masks beyond kAllIntrinsics).
  BinaryProblemWriter(const std::string& path, const Problem& camera_side,
                      int64_t num_points, int64_t num_observations);

  // The camera-side vector: 9 per BAL camera, or 6 per image then 5 per
  // intrinsic group.
  void WriteCameras(std::span<const double> cameras);
  void AppendPoint(const double* xyz, std::span<const int32_t> cameras,
                   std::span<const double> pixels);  // 2 per observation
  void Commit();

 private:
  void WriteHeader();
  void WriteRigs(const Problem& c);
  void Flush();
  void Write(int64_t offset, const void* data, int64_t bytes);

  AtomicOutputFile out_;
  BinaryProblemHeader h_;
  int64_t points_ = 0, observations_ = 0;  // written so far (flushed or buffered)
  int64_t flushed_points_ = 0, flushed_observations_ = 0;
  std::vector<double> xyz_, pixels_;
  std::vector<int64_t> offsets_;
  std::vector<int32_t> cameras_;
  bool cameras_written_ = false;
};

}  // namespace dba
