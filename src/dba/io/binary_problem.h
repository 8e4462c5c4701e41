// The dba binary problem format (version 1): a versioned, mmap/pread-friendly
// layout of a BalProblem, observations point-major, so a rank can read the
// points it owns without reading the rest (DESIGN.md §2, §5).
//
//   offset 0    header, 128 bytes:
//                 magic "DBAPROB\n" | u32 version = 1 | u32 byte-order mark
//                 0x01020304 | u32 camera model (1 = BAL, 9 parameters) |
//                 u32 camera size | u64 cameras | u64 points | u64 observations
//                 | u64 section offsets: cameras, points, point offsets,
//                 observation cameras, observation pixels | u64 file size |
//                 zero padding
//   sections, each starting at a multiple of 8 bytes:
//     cameras        f64[9 · cameras]
//     points         f64[3 · points]
//     point offsets  i64[points + 1]     observations of point k are
//                                          [offsets[k], offsets[k+1])
//     obs cameras    i32[observations]   (zero-padded to 8 bytes)
//     obs pixels     f64[2 · observations]
// All numbers little-endian. Counts are 64-bit.
//
// Thread safety: functions are independent; concurrent reads of one file are
// safe.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dba/io/temporary_file.h"
#include "dba/problem/bal_problem.h"

namespace dba {

struct BinaryProblemHeader {
  uint32_t version = 0;
  uint32_t camera_model = 0;
  uint32_t camera_size = 0;
  int64_t num_cameras = 0;
  int64_t num_points = 0;
  int64_t num_observations = 0;
  int64_t cameras_offset = 0;
  int64_t points_offset = 0;
  int64_t point_offsets_offset = 0;
  int64_t obs_camera_offset = 0;
  int64_t obs_pixel_offset = 0;
  int64_t file_size = 0;
};

// True if the file starts with the binary magic.
bool IsBinaryProblem(const std::string& path);

// Reads and checks the header against the file: magic, version, byte order,
// camera model, section layout and file size. Throws InputError.
BinaryProblemHeader ReadBinaryProblemHeader(const std::string& path);

// The whole problem. Throws InputError on any inconsistency (offsets not
// monotonic, ids out of range, non-finite values).
BalProblem ReadBinaryProblem(const std::string& path);

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

// Points with point_group[k] == group, their observations and all cameras
// (global ids; see ExtractShare for the local renumbering), read in chunks.
// `global_point` receives the global id of each point read.
BalProblem ReadBinaryPoints(const std::string& path, std::span<const int32_t> point_group,
                            int32_t group, std::vector<int64_t>* global_point);

// Only the cameras (9 per camera), or only the point coordinates (3 per point).
std::vector<double> ReadBinaryCameras(const std::string& path);
std::vector<double> ReadBinaryPointCoordinates(const std::string& path);

// Writes `problem` to path.tmp.<pid>, then renames it over `path`.
void WriteBinaryProblem(const BalProblem& problem, const std::string& path);

// Writes `output` as a copy of the binary problem `input` with its cameras
// and point coordinates replaced, streaming the observations through a
// buffer (they are never all in memory). Atomic like WriteBinaryProblem.
void WriteBinaryWithNewParameters(const std::string& input, const std::string& output,
                                  const std::vector<double>& cameras,
                                  const std::vector<double>& points);

// Streams a problem into the binary format when the counts are known ahead:
// cameras once, then points one by one in order with their observations.
// Everything goes to path.tmp.<pid>; Commit() checks that the counts were
// met, syncs and renames; a writer destroyed without Commit() removes the
// temporary. Memory: a buffer of a few MiB.
class BinaryProblemWriter {
 public:
  BinaryProblemWriter(const std::string& path, int64_t num_cameras, int64_t num_points,
                      int64_t num_observations);

  void WriteCameras(std::span<const double> cameras);  // 9 per camera
  void AppendPoint(const double* xyz, std::span<const int32_t> cameras,
                   std::span<const double> pixels);  // 2 per observation
  void Commit();

 private:
  void Flush();
  void Write(int64_t offset, const void* data, int64_t bytes);

  TemporaryFile out_;
  BinaryProblemHeader h_;
  int64_t points_ = 0, observations_ = 0;  // written so far (flushed or buffered)
  int64_t flushed_points_ = 0, flushed_observations_ = 0;
  std::vector<double> xyz_, pixels_;
  std::vector<int64_t> offsets_;
  std::vector<int32_t> cameras_;
  bool cameras_written_ = false;
};

}  // namespace dba
