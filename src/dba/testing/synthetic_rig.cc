// Small synthetic rig problems; see synthetic_rig.h.
#include "dba/testing/synthetic_rig.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "dba/camera/photo_camera.h"
#include "dba/camera/pose_step.h"
#include "dba/camera/rig_pose.h"

namespace dba::testing {
namespace {

// A pose (ω, t) with centre C looking along `forward` (+z), y roughly down.
void LookAlong(const Vec3& C, const Vec3& forward, double* pose) {
  const Vec3 z = forward.normalized();
  const Vec3 x = Vec3(0, 0, 1).cross(z).normalized();
  const Vec3 y = z.cross(x);
  Mat3 R;
  R.row(0) = x, R.row(1) = y, R.row(2) = z;
  const Eigen::AngleAxisd aa(R);
  const Vec3 omega = aa.angle() * aa.axis(), t = -R * C;
  for (int k = 0; k < 3; ++k) pose[k] = omega[k], pose[3 + k] = t[k];
}

// The camera side of the rig survey: frames, sensors, images; cameras sized.
Problem RigSide(const SyntheticRigOptions& o) {
  Problem p;
  p.model = CameraModel::kPhoto;
  const int groups = o.sensors;
  for (int f = 0; f < o.frames; ++f) {
    for (int s = 0; s < groups; ++s) {
      if (o.missing && s > 0 && (f + s) % 4 == 3) continue;
      p.image_frame.push_back(f);
      p.camera_intrinsics.push_back(s);
    }
  }
  p.sensor_kind.assign(groups, o.held_geometry ? kSensorHeld : kSensorRefined);
  p.sensor_kind[0] = kRigOrigin;
  p.cameras.assign(kPhotoPoseSize * (p.camera_intrinsics.size() + o.frames + groups) +
                       kPhotoIntrinsicsSize * groups, 0.0);
  for (int g = 0; g < groups; ++g) {
    const double intrinsics[5] = {500.0 + 10 * g, 320.0, 240.0, 0.01 * g, 0.0};
    std::copy_n(intrinsics, 5, p.intrinsics(g));
    if (g == 0) continue;
    // Sensor g: 0.3 m to the side per index, turned about the rig's y axis.
    const double yaw = 0.25 * ((g % 2) ? 1.0 : -1.0) * ((g + 1) / 2) / ((groups + 1) / 2);
    const Vec3 c(0.3 * g, 0.05 * g, -0.1 * g);
    const Vec3 omega(0.02 * g, yaw, -0.01 * g);
    const Vec3 t = -AngleAxisToRotation(omega) * c;
    double* s = p.cameras.data() + p.sensor_offset(g);
    for (int k = 0; k < 3; ++k) s[k] = omega[k], s[3 + k] = t[k];
  }
  for (int f = 0; f < o.frames; ++f) {
    const double a = 2.0 * M_PI * f / o.frames;
    const Vec3 C(10.0 * std::cos(a), 10.0 * std::sin(a), 1.0 + 0.3 * std::sin(3 * a));
    LookAlong(C, -C, p.cameras.data() + p.frame_offset(f));
  }
  ComposeRigImages(&p);
  return p;
}

}  // namespace

SyntheticProblem MakeSyntheticRig(const SyntheticRigOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(-2.0, 2.0), u01(0.0, 1.0);
  SyntheticProblem out;
  Problem& truth = out.truth;
  truth = RigSide(o);
  Problem& problem = out.problem;
  problem = truth;
  truth.point_offsets.push_back(0);
  problem.point_offsets.push_back(0);
  const double zero[2] = {0.0, 0.0};
  for (int k = 0; k < o.points; ++k) {
    const double X[3] = {u(rng), u(rng), u(rng)};
    std::vector<int32_t> seen;
    std::vector<double> clean;
    for (int64_t i = 0; i < truth.num_images(); ++i) {
      const int32_t g = truth.camera_intrinsics[i];
      const Vec2 px = PhotoResidual(LensModel::kRadial, truth.camera(i), truth.intrinsics(g), X, zero);
      if (u01(rng) > 0.7) continue;
      seen.push_back(static_cast<int32_t>(i));
      clean.push_back(px.x()), clean.push_back(px.y());
    }
    if (seen.size() < 2) continue;
    const double X0[3] = {X[0] + 0.05 * o.perturbation * n01(rng),
                          X[1] + 0.05 * o.perturbation * n01(rng),
                          X[2] + 0.05 * o.perturbation * n01(rng)};
    truth.points.insert(truth.points.end(), X, X + 3);
    problem.points.insert(problem.points.end(), X0, X0 + 3);
    for (size_t a = 0; a < seen.size(); ++a) {
      truth.obs_camera.push_back(seen[a]);
      problem.obs_camera.push_back(seen[a]);
      truth.obs_pixel.push_back(clean[2 * a]), truth.obs_pixel.push_back(clean[2 * a + 1]);
      problem.obs_pixel.push_back(clean[2 * a] + o.pixel_noise * n01(rng));
      problem.obs_pixel.push_back(clean[2 * a + 1] + o.pixel_noise * n01(rng));
    }
    truth.point_offsets.push_back(truth.num_observations());
    problem.point_offsets.push_back(problem.num_observations());
  }
  // Initial frames and sensors: turned by ~0.01 (0.003) rad and moved by
  // ~5 (1) cm, each as its own LM step would.
  auto perturb = [&](double* pose, double angle, double shift) {
    double d[6];
    for (int k = 0; k < 3; ++k) d[k] = angle * o.perturbation * n01(rng);
    for (int k = 3; k < 6; ++k) d[k] = shift * o.perturbation * n01(rng);
    PlusPose(pose, d, pose);
  };
  for (int f = 0; f < o.frames; ++f) perturb(problem.cameras.data() + problem.frame_offset(f), 0.01, 0.05);
  for (int g = 1; g < o.sensors; ++g) {
    perturb(problem.cameras.data() + problem.sensor_offset(g), 0.003, 0.01);
  }
  ComposeRigImages(&problem);
  return out;
}

}  // namespace dba::testing
