// Synthetic photogrammetric problems for tests; see synthetic_photo.h.
#include "dba/testing/synthetic_photo.h"

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
  t.cameras.resize(kPhotoPoseSize * n + kPhotoIntrinsicsSize * o.num_groups);
  for (int i = 0; i < n; ++i) {
    t.camera_intrinsics[i] = i % o.num_groups;
    PoseFromBal(bal.truth.camera(i), t.camera(i));
  }
  for (int gi = 0; gi < o.num_groups; ++gi) {
    double* c = t.intrinsics(gi);
    c[0] = 800.0 + 50.0 * uniform(rng);
    c[1] = 320.0 + 10.0 * uniform(rng);
    c[2] = 240.0 + 10.0 * uniform(rng);
    c[3] = 0.05 * uniform(rng);
    c[4] = 0.005 * uniform(rng);
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
      const Vec2 u = PhotoResidual(t.camera(i), t.intrinsics(t.camera_intrinsics[i]),
                                   t.point(k), zero);
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
  for (int gi = 0; gi < o.num_groups; ++gi) {
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
