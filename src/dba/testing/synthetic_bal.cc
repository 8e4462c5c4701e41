// Synthetic BAL problems for tests; see synthetic_bal.h.
#include "dba/testing/synthetic_bal.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "dba/camera/bal_camera.h"

namespace dba::testing {

SyntheticProblem MakeSyntheticBal(const SyntheticBalOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  SyntheticProblem s;
  Problem& t = s.truth;
  t.cameras.resize(kBalCameraSize * o.num_cameras);
  for (int i = 0; i < o.num_cameras; ++i) {
    // Camera centre on a circle of radius 10 at angle a, looking at the
    // origin: its -z axis points to the origin.
    const double a = 2.0 * M_PI * i / o.num_cameras + 0.1 * uniform(rng);
    const Vec3 centre(10 * std::cos(a), 10 * std::sin(a), 2.0 * uniform(rng));
    const Vec3 z = centre.normalized();  // camera +z points away from origin
    const Vec3 x = Vec3::UnitZ().cross(z).normalized();
    const Vec3 y = z.cross(x);
    Mat3 R;  // rows: camera axes in world coordinates
    R.row(0) = x;
    R.row(1) = y;
    R.row(2) = z;
    const Eigen::AngleAxisd aa(R);
    const Vec3 omega = aa.angle() * aa.axis();
    const Vec3 tr = -R * centre;
    double* c = t.camera(i);
    for (int k = 0; k < 3; ++k) c[k] = omega[k], c[3 + k] = tr[k];
    c[6] = 800.0 + 50.0 * uniform(rng);
    c[7] = 0.05 * uniform(rng);
    c[8] = 0.005 * uniform(rng);
  }
  t.points.resize(kPointSize * o.num_points);
  for (double& v : t.points) v = 3.0 * uniform(rng);
  t.point_offsets.push_back(0);
  std::vector<int32_t> cams(o.num_cameras);
  std::iota(cams.begin(), cams.end(), 0);
  for (int k = 0; k < o.num_points; ++k) {
    std::shuffle(cams.begin(), cams.end(), rng);
    const int track = 2 + static_cast<int>(rng() % std::max(1, o.max_track - 1));
    for (int a = 0; a < std::min(track, o.num_cameras); ++a) {
      const double zero[2] = {0.0, 0.0};
      const Vec2 u = BalResidual(t.camera(cams[a]), t.point(k), zero);
      t.obs_camera.push_back(cams[a]);
      t.obs_pixel.push_back(u.x());
      t.obs_pixel.push_back(u.y());
    }
    t.point_offsets.push_back(static_cast<int64_t>(t.obs_camera.size()));
  }
  Problem& p = s.problem;
  p = t;
  for (double& v : p.obs_pixel) v += o.pixel_noise * normal(rng);
  for (int i = 0; i < o.num_cameras; ++i) {
    double* c = p.camera(i);
    for (int k = 0; k < 3; ++k) {
      c[k] += o.rotation_perturbation * normal(rng);
      c[3 + k] += o.translation_perturbation * normal(rng);
    }
    c[6] *= 1.0 + o.intrinsics_perturbation * normal(rng);
    c[7] += o.intrinsics_perturbation * normal(rng);
    c[8] += 0.1 * o.intrinsics_perturbation * normal(rng);
  }
  for (double& v : p.points) v += o.point_perturbation * normal(rng);
  return s;
}

}  // namespace dba::testing
