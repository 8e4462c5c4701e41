// The gauge held by mapping the optimum back onto the input's frame; see
// gauge_hold.h for the similarity.
#include "dba/camera/gauge_hold.h"

#include "dba/camera/rig_pose.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dba {
namespace {

// The diagonal of the box holding every image's centre.
double CentreSpread(const CameraSide& side) {
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    const Vec3 c = CameraCentre(side.camera(i));
    lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  }
  return side.num_images() == 0 ? 0.0 : (hi - lo).norm();
}

int64_t FirstFixedImage(const CameraSide& side, int64_t from) {
  for (int64_t i = from; i < side.num_images(); ++i) {
    if (side.camera_fixed(i)) return i;
  }
  return -1;
}

}  // namespace

GaugeReference TakeGaugeReference(const CameraSide& side, bool external) {
  GaugeReference ref;
  if (external) {
    ref.hold = GaugeHold::kExternal;
    return ref;
  }
  if (side.num_images() == 0) return ref;
  const int64_t fixed = FirstFixedImage(side, 0);
  ref.anchor = std::max<int64_t>(fixed, 0);
  const Vec3 anchor = CameraCentre(side.camera(ref.anchor));
  const double apart = 1e-12 * CentreSpread(side);
  for (int64_t i = FirstFixedImage(side, ref.anchor + 1); fixed >= 0 && i >= 0;
       i = FirstFixedImage(side, i + 1)) {
    if ((CameraCentre(side.camera(i)) - anchor).norm() > apart) {
      ref.hold = GaugeHold::kFixedImages;
      return ref;
    }
  }
  ref.hold = fixed >= 0 ? GaugeHold::kFixedImage : GaugeHold::kFirstImage;
  std::copy_n(side.camera(ref.anchor), 6, ref.pose.begin());
  // With rigs the scale is held between two frames' origins (the anchor's
  // sensor in another frame), not by a sensor's place in its rig.
  auto other_frame = [&](int64_t i) {
    return !side.has_rigs() || (side.image_frame[i] != side.image_frame[ref.anchor] &&
                                side.camera_intrinsics[i] == side.camera_intrinsics[ref.anchor]);
  };
  // A held sensor away from its rig's origin holds the scale itself.
  bool scale_held = false;
  for (int64_t g = 0; side.has_rigs() && g < side.num_groups(); ++g) {
    const double* t = side.cameras.data() + side.sensor_offset(g) + 3;
    scale_held |= side.sensor_kind[g] == kSensorHeld && (t[0] != 0 || t[1] != 0 || t[2] != 0);
  }
  ref.rig_scale = scale_held;
  for (int64_t i = 0; i < side.num_images() && !scale_held; ++i) {
    const double d = (CameraCentre(side.camera(i)) - anchor).norm();
    if (i != ref.anchor && d > apart && other_frame(i)) {
      ref.second = i;
      ref.distance = d;
      break;
    }
  }
  return ref;
}

Similarity GaugeMapping(const GaugeReference& ref, const CameraSide& side) {
  Similarity s;
  if (ref.hold != GaugeHold::kFixedImage && ref.hold != GaugeHold::kFirstImage) return s;
  const double* a = side.camera(ref.anchor);
  if (ref.second >= 0) {
    const double d = (CameraCentre(side.camera(ref.second)) - CameraCentre(a)).norm();
    if (d > 0 && std::isfinite(ref.distance / d)) s.scale = ref.distance / d;
  }
  if (ref.hold == GaugeHold::kFixedImage) {
    s.translation = (1.0 - s.scale) * CameraCentre(a);
    return s;
  }
  // An anchor that did not move (no iteration, or it was held): the identity
  // exactly, so that nothing is rewritten to rounding.
  if (std::equal(ref.pose.begin(), ref.pose.end(), a) && s.scale == 1.0) return s;
  const Mat3 R_in = AngleAxisToRotation(Vec3(ref.pose[0], ref.pose[1], ref.pose[2]));
  const Mat3 R = AngleAxisToRotation(Vec3(a[0], a[1], a[2]));
  s.rotation = R_in.transpose() * R;
  s.translation =
      R_in.transpose() * (s.scale * Vec3(a[3], a[4], a[5]) - Vec3(ref.pose[3], ref.pose[4], ref.pose[5]));
  return s;
}

// Rigs: the frames (but those of fixed images) moved as poses, each
// sensor's place in its rig scaled with the world (its turn is relative and
// unchanged), the images composed anew. The anchor's frame keeps its input
// pose exactly when the anchor is its rig's origin.
void MoveRigs(const Similarity& s, const GaugeReference& ref, CameraSide* side) {
  std::vector<uint8_t> held(side->num_frames(), 0);
  for (int64_t i = 0; i < side->num_images(); ++i) {
    if (side->camera_fixed(i)) held[side->image_frame[i]] = 1;
  }
  MoveRigFrames(s, held, side);
  if (ref.hold == GaugeHold::kFirstImage &&
      side->sensor_kind[side->camera_intrinsics[ref.anchor]] == kRigOrigin) {
    std::copy(ref.pose.begin(), ref.pose.end(),
              side->cameras.data() + side->frame_offset(side->image_frame[ref.anchor]));
  }
  ComposeRigImages(side);
}

void MoveCameras(const Similarity& s, const GaugeReference& ref, CameraSide* side) {
  if (side->has_rigs()) return MoveRigs(s, ref, side);
  for (int64_t i = 0; i < side->num_images(); ++i) {
    if (!side->camera_fixed(i)) MovePose(s, side->camera(i));
  }
  if (ref.hold == GaugeHold::kFirstImage) {
    std::copy(ref.pose.begin(), ref.pose.end(), side->camera(ref.anchor));
  }
}

void MovePoints(const Similarity& s, std::vector<double>* points,
                const std::vector<uint8_t>& moved) {
  const int64_t n = static_cast<int64_t>(points->size()) / kPointSize;
  double* x = points->data();
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < n; ++k) {
    if (!moved.empty() && !moved[k]) continue;
    const Vec3 m = s.Apply(Vec3(x[3 * k], x[3 * k + 1], x[3 * k + 2]));
    x[3 * k] = m[0], x[3 * k + 1] = m[1], x[3 * k + 2] = m[2];
  }
}

std::string DescribeGauge(const GaugeReference& ref, const Similarity& moved_by) {
  const std::string second =
      ref.second >= 0 ? "its distance to image " + std::to_string(ref.second)
      : ref.rig_scale ? "the scale of the rig's held sensor places"
                      : "no scale (every centre at its)";
  char how[160];
  std::snprintf(how, sizeof how, " (the optimum mapped back: scale %.9g, rotation %.3g rad)",
                moved_by.scale, Eigen::AngleAxisd(moved_by.rotation).angle());
  switch (ref.hold) {
    case GaugeHold::kFree: return "free (--gauge free): where LM ended";
    case GaugeHold::kExternal: return "the camera priors or control points";
    case GaugeHold::kFixedImages: return "the images held fixed";
    case GaugeHold::kFixedImage:
      return "fixed image " + std::to_string(ref.anchor) + ", and " + second + how;
    case GaugeHold::kFirstImage:
      return "image " + std::to_string(ref.anchor) + "'s pose and " + second + how;
  }
  return "";
}

}  // namespace dba
