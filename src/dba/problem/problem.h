// A bundle-adjustment problem, held point-major, with one of two camera
// models (camera/bal_camera.h, camera/photo_camera.h):
//
//   kBal    one camera per image, 9 parameters (ω, t, f, k1, k2)
//   kPhoto  per image a pose (ω, t: 6 parameters) and per physical camera an
//           intrinsic group shared by the images taken with it: a lens model
//           (problem/lens_model.h: COLMAP's models and Brown) and its
//           parameters (the paper's 6 exterior + 5 interior unknowns are a
//           RADIAL group)
//
// All camera-side parameters live in one vector `cameras`: the images' 9 or 6
// parameters each, then (kPhoto) the intrinsic groups', intrinsics_size
// slots each (a group uses the first LensModelParams(its model) of them; the
// rest are zero and never unknowns). The LM loop steps that vector as a whole.
//
// Two types: a CameraSide (the model, the camera-side parameters, the images'
// groups, what is held fixed), which is what the main rank of a distributed
// solve holds and what the unknowns are laid out from; and a Problem, a
// camera side plus points and their observations. A Problem is also the
// share of one rank (docs/design.md §4): its points, their observations and
// the cameras they touch, renumbered locally. A single process is one rank
// holding everything.
//
// Rigs (docs/design.md §1.7): when `image_frame` is not empty, each image
// is one sensor (its intrinsic group) of a rig fired in one exposure (its
// frame), and its pose is derived, image = sensor_from_rig ∘ rig_from_world
// (camera/rig_pose.h); the unknowns are then the frames' and the sensors'
// poses, held after the groups in `cameras`.
//
// Control points (ground control) are points with a prior on their
// coordinates (PointPrior), held sparsely beside the points.
//
// Memory per observation: one 32-bit camera id and two doubles (20 bytes),
// plus the 64-bit point offsets (8 bytes per point).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "dba/problem/lens_model.h"

namespace dba {

inline constexpr int kBalCameraSize = 9;  // angle-axis r[3], t[3], f, k1, k2
inline constexpr int kPointSize = 3;
inline constexpr int kPhotoPoseSize = 6;        // ω[3], t[3]
// Slots per intrinsic group unless a problem says otherwise: RADIAL's f,
// cx, cy, k1, k2 (the paper's model).
inline constexpr int kPhotoIntrinsicsSize = 5;

enum class CameraModel : int32_t { kBal = 0, kPhoto = 1 };

// A group's sensor pose on its rig: the rig's origin (identity, no
// unknown), or a sensor_from_rig that the solve refines or holds.
enum SensorKind : uint8_t { kRigOrigin = 0, kSensorRefined = 1, kSensorHeld = 2 };

// Bits of a group's parameters (bit j: its model's parameter j), for
// fixed_intrinsics. The named bits are RADIAL's (f, cx, cy, k1, k2; all five
// are kAllIntrinsics), which also name the first parameters of
// SIMPLE_PINHOLE, SIMPLE_RADIAL and Brown; other models' masks come from
// LensModelParamMask and LensModelParamIndex.
enum IntrinsicBit : uint16_t {
  kIntrinsicF = 1, kIntrinsicCx = 2, kIntrinsicCy = 4, kIntrinsicK1 = 8, kIntrinsicK2 = 16,
  kAllIntrinsics = 31,
};

struct CameraSide {
  CameraModel model = CameraModel::kBal;
  // kPhoto: slots per intrinsic group, at least every group's model's
  // parameter count (at most kMaxIntrinsics).
  int32_t intrinsics_size = kPhotoIntrinsicsSize;
  // Camera-side parameters: camera_size() per image (a BAL camera, or a
  // pose), then, for kPhoto, intrinsics_size per intrinsic group.
  std::vector<double> cameras;
  // kPhoto: each group's lens model; empty means every group is RADIAL.
  std::vector<LensModel> group_models;
  // kPhoto: the intrinsic group of each image (size num_images()).
  std::vector<int32_t> camera_intrinsics;
  // What is held fixed (fixed parameters are not unknowns of the solve).
  // fixed_cameras: empty (none fixed), or one flag per image (the whole
  // pose/camera). fixed_intrinsics: kPhoto, empty (none fixed) or per group
  // a mask of the parameters held fixed (bit j: parameter j).
  std::vector<uint8_t> fixed_cameras;
  std::vector<uint16_t> fixed_intrinsics;
  // Rigs (kPhoto; both empty without): per image its frame, per group its
  // SensorKind. With rigs `cameras` holds after the groups' slots 6 per
  // frame (rig_from_world) and then 6 per group (sensor_from_rig; zero for
  // kRigOrigin), and the images' poses are composed from them. A frame is
  // held fixed when one of its images is.
  std::vector<int32_t> image_frame;
  std::vector<uint8_t> sensor_kind;

  int camera_size() const {
    return model == CameraModel::kBal ? kBalCameraSize : kPhotoPoseSize;
  }
  // Images; for kPhoto the poses, not the intrinsic groups.
  int64_t num_images() const {
    return model == CameraModel::kBal
               ? static_cast<int64_t>(cameras.size()) / kBalCameraSize
               : static_cast<int64_t>(camera_intrinsics.size());
  }
  // Intrinsic groups (kPhoto; 0 for kBal).
  int64_t num_groups() const {
    if (has_rigs()) return static_cast<int64_t>(sensor_kind.size());
    return model == CameraModel::kBal
               ? 0
               : (static_cast<int64_t>(cameras.size()) - kPhotoPoseSize * num_images()) /
                     intrinsics_size;
  }
  bool has_rigs() const { return !image_frame.empty(); }
  // Frames (exposures): with rigs, those in `cameras`; else one per image.
  int64_t num_frames() const {
    if (!has_rigs()) return num_images();
    return (static_cast<int64_t>(cameras.size()) - frames_offset()) / kPhotoPoseSize -
           num_groups();
  }
  // With rigs: where frame f's rig_from_world and group g's sensor_from_rig
  // start in `cameras`.
  int64_t frames_offset() const { return intrinsics_offset(num_groups()); }
  int64_t frame_offset(int64_t f) const { return frames_offset() + kPhotoPoseSize * f; }
  int64_t sensor_offset(int64_t g) const {
    return static_cast<int64_t>(cameras.size()) - kPhotoPoseSize * (num_groups() - g);
  }
  // Group g's lens model (kPhoto).
  LensModel group_model(int64_t g) const {
    return group_models.empty() ? LensModel::kRadial : group_models[g];
  }
  double* camera(int64_t i) { return cameras.data() + camera_size() * i; }
  const double* camera(int64_t i) const { return cameras.data() + camera_size() * i; }
  // Intrinsic group g (kPhoto).
  double* intrinsics(int64_t g) { return cameras.data() + intrinsics_offset(g); }
  const double* intrinsics(int64_t g) const { return cameras.data() + intrinsics_offset(g); }
  // Where group g's parameters start in `cameras`.
  int64_t intrinsics_offset(int64_t g) const {
    return kPhotoPoseSize * num_images() + int64_t{intrinsics_size} * g;
  }
  bool camera_fixed(int64_t i) const { return !fixed_cameras.empty() && fixed_cameras[i]; }
  // The intrinsic parameters of group g that are unknowns: its model's
  // (not metadata) and not held fixed.
  uint16_t intrinsics_free_mask(int64_t g) const {
    const uint16_t model = LensModelParamMask(group_model(g));
    return fixed_intrinsics.empty() ? model
                                    : static_cast<uint16_t>(model & ~fixed_intrinsics[g]);
  }

  // Every array, in one fixed order (cameras, group_models,
  // camera_intrinsics, fixed_cameras, fixed_intrinsics, image_frame,
  // sensor_kind): the one list of the fields for code that treats them alike
  // (sending a share, sizing). `f` gets each vector.
  template <class F>
  void ForEachArray(F&& f) {
    f(cameras), f(group_models), f(camera_intrinsics), f(fixed_cameras), f(fixed_intrinsics);
    f(image_frame), f(sensor_kind);
  }
  template <class F>
  void ForEachArray(F&& f) const {
    f(cameras), f(group_models), f(camera_intrinsics), f(fixed_cameras), f(fixed_intrinsics);
    f(image_frame), f(sensor_kind);
  }
  // Bytes held by the arrays (capacity, not size).
  int64_t MemoryBytes() const { return ArrayBytes(*this); }
  // Every image its own exposure again: the frames' and sensors' poses
  // dropped, the images' (composed) poses kept.
  void DropRigs() {
    if (!has_rigs()) return;
    cameras.resize(static_cast<size_t>(frames_offset()));
    image_frame.clear();
    sensor_kind.clear();
  }

 protected:
  template <class T>
  static int64_t ArrayBytes(const T& t) {
    int64_t bytes = 0;
    t.ForEachArray([&](const auto& v) {
      bytes += static_cast<int64_t>(v.capacity() *
                                    sizeof(typename std::decay_t<decltype(v)>::value_type));
    });
    return bytes;
  }
};

// A prior on point `point`'s coordinates (a ground control point): the
// residual r = w ∘ (X - position), w = 1/σ per axis, under the squared loss
// (rcs/eliminate_point.h adds it to the point's own block).
struct PointPrior {
  int64_t point = 0;
  double position[3] = {0.0, 0.0, 0.0};
  double weight[3] = {0.0, 0.0, 0.0};
};

struct Problem : CameraSide {
  Problem() = default;
  // A problem with `side`'s cameras and no points yet.
  explicit Problem(CameraSide side) : CameraSide(std::move(side)) {}

  // Point coordinates, kPointSize per point.
  std::vector<double> points;
  // Observations of point k are [point_offsets[k], point_offsets[k+1]).
  // Size num_points() + 1, point_offsets[0] == 0.
  std::vector<int64_t> point_offsets;
  // Image seeing each observation, and the observed pixel (x, y).
  std::vector<int32_t> obs_camera;
  std::vector<double> obs_pixel;
  // Priors on points (control points), sorted by point, at most one each.
  std::vector<PointPrior> point_priors;

  CameraSide& camera_side() { return *this; }
  const CameraSide& camera_side() const { return *this; }
  int64_t num_points() const {
    return static_cast<int64_t>(points.size()) / kPointSize;
  }
  int64_t num_observations() const {
    return static_cast<int64_t>(obs_camera.size());
  }
  double* point(int64_t k) { return points.data() + kPointSize * k; }
  const double* point(int64_t k) const { return points.data() + kPointSize * k; }
  const double* pixel(int64_t obs) const { return obs_pixel.data() + 2 * obs; }
  // Point k's prior, or null.
  const PointPrior* point_prior(int64_t k) const {
    if (point_priors.empty()) return nullptr;
    const auto it = std::lower_bound(point_priors.begin(), point_priors.end(), k,
                                     [](const PointPrior& p, int64_t x) { return p.point < x; });
    return it != point_priors.end() && it->point == k ? &*it : nullptr;
  }

  // The camera side's arrays, then the points' and observations' (points,
  // point_offsets, obs_camera, obs_pixel, point_priors).
  template <class F>
  void ForEachArray(F&& f) {
    CameraSide::ForEachArray(f);
    f(points), f(point_offsets), f(obs_camera), f(obs_pixel), f(point_priors);
  }
  template <class F>
  void ForEachArray(F&& f) const {
    CameraSide::ForEachArray(f);
    f(points), f(point_offsets), f(obs_camera), f(obs_pixel), f(point_priors);
  }
  int64_t MemoryBytes() const { return ArrayBytes(*this); }
};

}  // namespace dba
