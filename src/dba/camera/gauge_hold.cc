// The gauge held by mapping the optimum back onto the input's frame; see
// gauge_hold.h for the similarities (docs/design.md §1.6).
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

// Whether a held sensor away from its rig's origin holds the scale.
bool RigHoldsScale(const CameraSide& side) {
  for (int64_t g = 0; side.has_rigs() && g < side.num_groups(); ++g) {
    const double* t = side.cameras.data() + side.sensor_offset(g) + 3;
    if (side.sensor_kind[g] == kSensorHeld && (t[0] != 0 || t[1] != 0 || t[2] != 0)) return true;
  }
  return false;
}

PoseSetMean MeanOfImages(const CameraSide& side) {
  return MeanOfPoses(side.cameras.data(), side.num_images(), side.camera_size());
}

// The scale keeping ρ₀ (1 where it is not a finite positive number).
double SpreadScale(const GaugeReference& ref, double spread) {
  const double s = ref.mean.spread / spread;
  return ref.rig_scale || !(std::isfinite(s) && s > 0) ? 1.0 : s;
}

Mat3 RotationOf(const double* pose) { return AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])); }
Vec3 TranslationOf(const double* pose) { return Vec3(pose[3], pose[4], pose[5]); }

Similarity ColmapMapping(const GaugeReference& ref, const CameraSide& side) {
  Similarity s;
  const double* a = side.camera(ref.anchor);
  const bool second_held = ref.second < 0 || side.camera(ref.second)[3] == ref.second_tx;
  if (std::equal(ref.pose.begin(), ref.pose.end(), a) && second_held) return s;
  const Mat3 Ra0 = RotationOf(ref.pose.data()), Ra = RotationOf(a);
  const Vec3 ta0 = TranslationOf(ref.pose.data()), ta = TranslationOf(a);
  if (ref.second >= 0 && !ref.rig_scale) {
    const double* b = side.camera(ref.second);
    const Mat3 Rba = RotationOf(b) * Ra.transpose();
    const double scale = (ref.second_tx - (Rba * ta0)[0]) / (TranslationOf(b) - Rba * ta)[0];
    if (std::isfinite(scale) && scale > 0) s.scale = scale;
  }
  s.rotation = Ra0.transpose() * Ra;
  s.translation = Ra0.transpose() * (s.scale * ta - ta0);
  return s;
}

}  // namespace

GaugeReference TakeGaugeReference(const CameraSide& side, GaugeRule rule,
                                  std::span<const int32_t> read_order) {
  GaugeReference ref;
  if (rule == GaugeRule::kFree || side.num_images() == 0) return ref;
  ref.rig_scale = RigHoldsScale(side);
  ref.mean = MeanOfImages(side);
  const int64_t fixed = FirstFixedImage(side, 0);
  if (fixed >= 0) {
    const Vec3 anchor = CameraCentre(side.camera(fixed));
    const double apart = 1e-12 * CentreSpread(side);
    for (int64_t i = FirstFixedImage(side, fixed + 1); i >= 0; i = FirstFixedImage(side, i + 1)) {
      if ((CameraCentre(side.camera(i)) - anchor).norm() > apart) {
        ref.hold = GaugeHold::kFixedImages;
        return ref;
      }
    }
    ref.hold = GaugeHold::kFixedImage;
    ref.anchor = fixed;
    return ref;
  }
  if (rule == GaugeRule::kHold) {
    ref.hold = GaugeHold::kMean;
    return ref;
  }
  ref.hold = GaugeHold::kColmap;
  ref.anchor = read_order.empty() ? 0 : read_order[0];
  if (side.num_images() > 1) ref.second = read_order.size() > 1 ? read_order[1] : 1;
  std::copy_n(side.camera(ref.anchor), 6, ref.pose.begin());
  if (ref.second >= 0) ref.second_tx = side.camera(ref.second)[3];
  return ref;
}

Similarity GaugeMapping(const GaugeReference& ref, const CameraSide& side) {
  Similarity s;
  switch (ref.hold) {
    case GaugeHold::kFree:
    case GaugeHold::kExternal:
    case GaugeHold::kFixedImages: return s;
    case GaugeHold::kColmap: return ColmapMapping(ref, side);
    case GaugeHold::kFixedImage:
      s.scale = SpreadScale(ref, MeanOfImages(side).spread);
      s.translation = (1.0 - s.scale) * CameraCentre(side.camera(ref.anchor));
      return s;
    case GaugeHold::kMean: break;
  }
  const PoseSetMean m = MeanOfImages(side);
  // Nothing moved (no iteration): the identity exactly, so that nothing is
  // rewritten to rounding.
  if (m == ref.mean) return s;
  s.scale = SpreadScale(ref, m.spread);
  s.rotation = ref.mean.orientation.transpose() * m.orientation;
  s.translation = ref.mean.centroid - s.scale * (s.rotation * m.centroid);
  return s;
}

void MoveCameras(const Similarity& s, CameraSide* side) {
  if (side->has_rigs()) {
    // The frames of fixed images stay; sensors' places scale with the world.
    std::vector<uint8_t> held(side->num_frames(), 0);
    for (int64_t i = 0; i < side->num_images(); ++i) {
      if (side->camera_fixed(i)) held[side->image_frame[i]] = 1;
    }
    MoveRigFrames(s, held, side);
    ComposeRigImages(side);
    return;
  }
  for (int64_t i = 0; i < side->num_images(); ++i) {
    if (!side->camera_fixed(i)) MovePose(s, side->camera(i));
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

std::string DescribeGauge(const GaugeReference& ref, const Similarity& moved_by,
                          std::span<const int64_t> image_ids) {
  auto image = [&](int64_t i) {
    return "image " + (image_ids.empty() ? std::to_string(i) + " (0-based)"
                                         : std::to_string(image_ids[i]));
  };
  const std::string rig = " (the rigs' held sensor places hold the scale)";
  const std::string scale = ref.rig_scale ? rig
                            : ref.mean.spread == 0 ? " (every centre at one place: no scale)"
                                                   : "";
  char how[160];
  std::snprintf(how, sizeof how, " (the optimum mapped back: scale %.9g, rotation %.3g rad)",
                moved_by.scale, Eigen::AngleAxisd(moved_by.rotation).angle());
  switch (ref.hold) {
    case GaugeHold::kFree: return "free (--gauge free): where LM ended";
    case GaugeHold::kExternal: return "the camera priors or control points";
    case GaugeHold::kFixedImages: return "the images held fixed";
    case GaugeHold::kFixedImage:
      return "fixed " + image(ref.anchor) + ", and the centres' RMS spread" + scale + how;
    case GaugeHold::kMean:
      return "the centres' centroid, RMS spread and mean orientation" + scale + how;
    case GaugeHold::kColmap:
      return "COLMAP's: " + image(ref.anchor) + "'s pose" +
             (ref.second >= 0 ? " and " + image(ref.second) + "'s x translation" : "") +
             (ref.rig_scale ? rig : "") + how;
  }
  return "";
}

}  // namespace dba
