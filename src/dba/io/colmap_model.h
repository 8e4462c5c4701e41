// COLMAP sparse models in memory: cameras, images (poses and 2D points) and
// points3D (positions, colours and tracks), held exactly as the files hold
// them so that read -> write reproduces them (same entries, same order, same
// values bit for bit).
//
// Files (COLMAP's layouts, see colmap_text.h and colmap_binary.h):
//   cameras.{txt,bin}   CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]
//   images.{txt,bin}    IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME,
//                       POINTS2D[] as (X, Y, POINT3D_ID)
//   points3D.{txt,bin}  POINT3D_ID X Y Z R G B ERROR, TRACK[] as
//                       (IMAGE_ID, POINT2D_IDX)
// Conventions: the quaternion is (qw, qx, qy, qz) and with tvec maps world ->
// camera, x_cam = R(q) X + t; pixel coordinates have the origin at the
// top-left corner of the top-left pixel.
//
// Ids have COLMAP's widths: camera_id and image_id are 32-bit unsigned,
// point3D_id 64-bit (stored here as int64_t with -1 = "no 3D point"; a file
// holding a point3D_id >= 2^63 other than COLMAP's invalid marker is refused).
//
// COLMAP >= 3.12 may also write rigs and frames files beside these; they are
// not read (the three files above hold everything bundle adjustment needs).
//
// Thread safety: all functions are pure or touch only the files they name;
// distinct models/directories may be used from different threads.
#pragma once

#include "dba/problem/lens_model.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace dba {

// COLMAP's camera models (sensor/models.h): the lens models
// (problem/lens_model.h) that are COLMAP's, with COLMAP's ids.
using ColmapCameraModelInfo = LensModelInfo;

// All models COLMAP defines, in id order (ids 0..17).
std::span<const ColmapCameraModelInfo> ColmapCameraModels();
// nullptr when COLMAP has no such model.
const ColmapCameraModelInfo* FindColmapCameraModel(std::string_view name);
const ColmapCameraModelInfo* FindColmapCameraModel(int32_t id);

inline constexpr int64_t kColmapNoPoint3D = -1;

struct ColmapCamera {
  uint32_t camera_id = 0;
  int32_t model_id = -1;  // see ColmapCameraModels()
  uint64_t width = 0;
  uint64_t height = 0;
  std::vector<double> params;  // exactly the model's parameter count

  // The model's name ("SIMPLE_RADIAL"), or "UNKNOWN(<id>)".
  std::string ModelName() const;
  bool operator==(const ColmapCamera&) const = default;
};

struct ColmapPoint2D {
  double x = 0;
  double y = 0;
  int64_t point3D_id = kColmapNoPoint3D;
  bool operator==(const ColmapPoint2D&) const = default;
};

struct ColmapImage {
  uint32_t image_id = 0;
  std::array<double, 4> qvec{1, 0, 0, 0};  // qw, qx, qy, qz (world -> camera)
  std::array<double, 3> tvec{0, 0, 0};
  uint32_t camera_id = 0;
  std::string name;
  std::vector<ColmapPoint2D> points2D;  // all of them, with or without 3D point
  bool operator==(const ColmapImage&) const = default;
};

struct ColmapTrackElement {
  uint32_t image_id = 0;
  uint32_t point2D_idx = 0;  // index into that image's points2D
  bool operator==(const ColmapTrackElement&) const = default;
};

struct ColmapPoint3D {
  int64_t point3D_id = 0;
  std::array<double, 3> xyz{0, 0, 0};
  std::array<uint8_t, 3> rgb{0, 0, 0};
  double error = 0;  // mean reprojection error in pixels (COLMAP: -1 = unknown)
  std::vector<ColmapTrackElement> track;
  bool operator==(const ColmapPoint3D&) const = default;
};

// Entries in file order; ids need not be sorted or contiguous.
// COLMAP >= 3.12's rigs and frames (io/colmap_rigs.cc reads them, text or
// binary). A sensor is a camera (type 0, its id a camera id) or another
// kind (1: IMU; kept, not modelled); a rig has a reference sensor at its
// origin and others with, when known, their sensor_from_rig pose. A frame is
// one exposure of a rig: its rig_from_world and the data each sensor took
// (a camera's: an image id). COLMAP >= 3.12 takes each image's pose from its
// frame.
struct ColmapSensor {
  int32_t type = 0;  // 0: camera
  uint32_t id = 0;
  bool has_pose = false;  // (other sensors only)
  std::array<double, 4> qvec{1, 0, 0, 0};  // sensor_from_rig, w x y z
  std::array<double, 3> tvec{0, 0, 0};
  bool operator==(const ColmapSensor&) const = default;
};

struct ColmapRig {
  uint32_t rig_id = 0;
  ColmapSensor ref;                    // the rig's origin
  std::vector<ColmapSensor> sensors;   // the others, in file order
  bool operator==(const ColmapRig&) const = default;
};

struct ColmapFrameData {
  int32_t type = 0;  // the sensor's
  uint32_t sensor_id = 0;
  uint64_t data_id = 0;  // a camera's: the image id
  bool operator==(const ColmapFrameData&) const = default;
};

struct ColmapFrame {
  uint32_t frame_id = 0, rig_id = 0;
  std::array<double, 4> qvec{1, 0, 0, 0};  // rig_from_world, w x y z
  std::array<double, 3> tvec{0, 0, 0};
  std::vector<ColmapFrameData> data;
  bool operator==(const ColmapFrame&) const = default;
};

struct ColmapModel {
  std::vector<ColmapCamera> cameras;
  std::vector<ColmapImage> images;
  std::vector<ColmapPoint3D> points3D;
  // A 3.12 model's rigs and frames, text or binary, in file order; both
  // empty for older models.
  std::vector<ColmapRig> rigs;
  std::vector<ColmapFrame> frames;

  // Sum of track lengths (the residual pairs of bundle adjustment).
  int64_t NumObservations() const;
  // 2D points that have a 3D point (equals NumObservations() in a valid model).
  int64_t NumPoints2DWithPoint3D() const;
  bool operator==(const ColmapModel&) const = default;
};

// The first difference between two models, compared field by field with
// doubles compared bit for bit (so -0.0 != 0.0); "" when they are identical.
// For tests and diagnostics.
std::string FirstColmapModelDifference(const ColmapModel& a, const ColmapModel& b);

// Checks the model's structure and throws dba::InputError naming `dir`'s file
// (cameras/images/points3D + `extension`) on the first problem: duplicate ids,
// a camera model COLMAP does not define or a wrong parameter count, an image
// whose camera is missing, non-finite numbers (params, qvec, tvec, 2D points,
// xyz, error), a track element naming a missing image or a point2D_idx out of
// range or a 2D point that does not point back, a duplicated track element, a
// 2D point naming a missing 3D point or one whose track does not list it.
// The readers call it; no geometric checks.
void ValidateColmapModel(const ColmapModel& model, const std::string& dir,
                         const std::string& extension);

// ---------------------------------------------------------------------------
// Directory-level reading.

enum class ColmapFormat { kText, kBinary };

// The format of the model in `dir`: binary when cameras.bin, images.bin and
// points3D.bin all exist (COLMAP's own preference), else text when
// cameras.txt, images.txt and points3D.txt all exist, else nullopt.
std::optional<ColmapFormat> DetectColmapFormat(const std::string& dir);

// Reads the model in `dir` (the directory holding the three files, e.g.
// <project>/sparse/0), text or binary as DetectColmapFormat says, and
// validates it. Throws dba::InputError when `dir` holds no complete model
// (naming what is missing) or on any malformed content.
ColmapModel ReadColmapModel(const std::string& dir);

// The name of every file a model directory may hold that the reader takes:
// cameras, images, points3D, rigs and frames, .txt then .bin.
std::span<const char* const> ColmapModelFiles();

// True when `dir` holds COLMAP >= 3.12 rigs or frames files (text or binary).
bool HasRigsOrFrames(const std::string& dir);

// ---------------------------------------------------------------------------
// COLMAP cameras as intrinsic groups: COLMAP's model ids are dba's LensModel
// ids (problem/lens_model.h) and its parameters are a group's, in the same
// order, so a camera's params are a group's as they are.

// The lens model of `camera`. Throws dba::InputError(file, 0, ...) for an
// unknown model id or a parameter count that is not its model's. `file`
// names where the camera came from, e.g. "<dir>/cameras.bin".
LensModel LensModelOfColmapCamera(const ColmapCamera& camera,
                                  const std::string& file = "COLMAP cameras");

}  // namespace dba
