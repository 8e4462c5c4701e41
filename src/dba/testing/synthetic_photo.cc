// Synthetic photogrammetric problems for tests; see synthetic_photo.h.
#include "dba/testing/synthetic_photo.h"

#include "dba/camera/typical_lens.h"

#include <Eigen/Geometry>
#include <random>

#include "dba/camera/photo_camera.h"

namespace dba::testing {
namespace {

// BAL camera (looks down -z, y up) -> COLMAP pose: flip the camera's y and z.
void PoseFromBal(const double* bal, double* pose) {
  const Mat3 flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Mat3 R = flip * AngleAxisToRotation(Vec3(bal[0], bal[1], bal[2]));
  const Eigen::AngleAxisd aa(R);
  const Vec3 omega = aa.angle() * aa.axis();
  const Vec3 t = flip * Vec3(bal[3], bal[4], bal[5]);
  for (int k = 0; k < 3; ++k) pose[k] = omega[k], pose[3 + k] = t[k];
}

}  // namespace

SyntheticProblem MakeSyntheticPhoto(const SyntheticPhotoOptions& o) {
  SyntheticBalOptions g = o.geometry;
  g.pixel_noise = 0.0;
  g.intrinsics_perturbation = 0.0;
  const SyntheticProblem bal = MakeSyntheticBal(g);
  std::mt19937 rng(o.geometry.seed + 7919);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);

  SyntheticProblem s;
  Problem& t = s.truth;
  t.model = CameraModel::kPhoto;
  const int n = static_cast<int>(bal.truth.num_images());
  t.camera_intrinsics.resize(n);
  const bool radial = o.lens_model == LensModel::kRadial;
  if (!radial) {
    t.group_models.assign(o.num_groups, o.lens_model);
    t.intrinsics_size = LensModelParams(o.lens_model);
  }
  t.cameras.resize(kPhotoPoseSize * n + int64_t{t.intrinsics_size} * o.num_groups);
  for (int i = 0; i < n; ++i) {
    t.camera_intrinsics[i] = i % o.num_groups;
    PoseFromBal(bal.truth.camera(i), t.camera(i));
  }
  for (int gi = 0; gi < o.num_groups; ++gi) {
    // RADIAL's values (the same draws for every model, so a seed gives
    // the same focal length), or the model's typical ones at that focal.
    double c[5];
    c[0] = 800.0 + 50.0 * uniform(rng);
    c[1] = 320.0 + 10.0 * uniform(rng);
    c[2] = 240.0 + 10.0 * uniform(rng);
    c[3] = 0.05 * uniform(rng);
    c[4] = 0.005 * uniform(rng);
    const std::vector<double> values =
        radial ? std::vector<double>(c, c + 5) : TypicalLensParams(o.lens_model, c[0], 640.0, 480.0);
    std::copy(values.begin(), values.end(), t.intrinsics(gi));
  }
  t.points = bal.truth.points;
  t.point_offsets = bal.truth.point_offsets;
  t.obs_camera = bal.truth.obs_camera;
  t.obs_pixel.resize(2 * t.obs_camera.size());
  for (int64_t obs = 0; obs < t.num_observations(); ++obs) {
    t.obs_pixel[2 * obs] = t.obs_pixel[2 * obs + 1] = 0.0;
  }
  for (int64_t k = 0; k < t.num_points(); ++k) {
    for (int64_t obs = t.point_offsets[k]; obs < t.point_offsets[k + 1]; ++obs) {
      const int32_t i = t.obs_camera[obs];
      const double zero[2] = {0.0, 0.0};
      const int32_t g = t.camera_intrinsics[i];
      const Vec2 u = PhotoResidual(t.group_model(g), t.camera(i), t.intrinsics(g), t.point(k), zero);
      t.obs_pixel[2 * obs] = u.x();
      t.obs_pixel[2 * obs + 1] = u.y();
    }
  }

  Problem& p = s.problem;
  p = t;
  for (double& v : p.obs_pixel) v += o.geometry.pixel_noise * normal(rng);
  for (int i = 0; i < n; ++i) {
    // The same pose perturbation as the BAL problem's.
    PoseFromBal(bal.problem.camera(i), p.camera(i));
  }
  for (int gi = 0; gi < o.num_groups && !radial; ++gi) {
    // Focal lengths relative, principal point in pixels, extras relative.
    const LensModel m = o.lens_model;
    double* c = p.intrinsics(gi);
    const uint16_t free = LensModelParamMask(m);
    const int first_extra = LensModelParamIndex(m, "fy") ? 4 : 3;
    for (int j = 0; j < LensModelParams(m); ++j) {
      if (!(free & (1u << j))) continue;
      const std::string name = LensModelParamName(m, j);
      if (name == "cx" || name == "cy") {
        c[j] += o.principal_perturbation * normal(rng);
      } else if (j < first_extra) {
        c[j] *= 1.0 + o.focal_perturbation * normal(rng);
      } else {
        c[j] += o.distortion_perturbation * (std::abs(c[j]) + 1e-3) * normal(rng);
      }
    }
  }
  for (int gi = 0; gi < o.num_groups && radial; ++gi) {
    double* c = p.intrinsics(gi);
    c[0] *= 1.0 + o.focal_perturbation * normal(rng);
    c[1] += o.principal_perturbation * normal(rng);
    c[2] += o.principal_perturbation * normal(rng);
    c[3] += o.distortion_perturbation * normal(rng);
    c[4] += 0.1 * o.distortion_perturbation * normal(rng);
  }
  p.points = bal.problem.points;
  return s;
}

}  // namespace dba::testing
