// Rigs of the synthetic survey; see rig_survey.h.
#include "dba/synthetic/rig_survey.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "dba/camera/pose_similarity.h"
#include "dba/camera/rig_pose.h"

namespace dba {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A sensor whose axes in N are R_N_from_sensor, at centre c in N.
Pose6 SensorPose(const Mat3& N_from_sensor, const Vec3& c) {
  const Mat3 R = N_from_sensor.transpose();
  const Eigen::AngleAxisd aa(R);
  const Vec3 omega = aa.angle() * aa.axis(), t = -R * c;
  return {omega[0], omega[1], omega[2], t[0], t[1], t[2]};
}

Mat3 Rotation(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// The named rig about the nadir frame N.
std::vector<Pose6> NominalAboutNadir(const std::string& name) {
  std::vector<Pose6> s;
  const Vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  if (name == "oblique5") {
    s.push_back(SensorPose(Mat3::Identity(), Vec3::Zero()));
    // Fore (towards +x along the strip), aft, left, right: the optical axis
    // turned 45° from z towards that side.
    const Vec3 sides[4] = {x, -x, -y, y};
    for (const Vec3& d : sides) {
      const Vec3 axis = z.cross(d);  // turns z towards d
      s.push_back(SensorPose(Rotation(axis, 45.0 * kDegree), 0.1 * d));
    }
  } else if (name == "stereo") {
    s.push_back(SensorPose(Mat3::Identity(), Vec3::Zero()));
    s.push_back(SensorPose(Mat3::Identity(), Vec3(0.6, 0, 0)));
  } else if (name == "ring6") {
    for (int k = 0; k < 6; ++k) {
      const double azimuth = 60.0 * k * kDegree;
      const Vec3 d(std::cos(azimuth), std::sin(azimuth), 0.0);
      s.push_back(SensorPose(Rotation(z.cross(d), 45.0 * kDegree), 0.15 * d));
    }
  } else {
    throw std::invalid_argument("--rig: unknown rig '" + name + "' (known: oblique5, stereo, ring6)");
  }
  return s;
}

Pose6 ComposeInverse(const Pose6& a, const Pose6& b) {
  Pose6 out;
  ComposeWithInverse(a.data(), b.data(), out.data());
  return out;
}

// About the first sensor: S_s ∘ S_0⁻¹, the first exactly the identity.
std::vector<Pose6> AboutFirst(const std::vector<Pose6>& about_nadir) {
  std::vector<Pose6> out;
  for (const Pose6& s : about_nadir) out.push_back(ComposeInverse(s, about_nadir[0]));
  out[0].fill(0.0);
  return out;
}

// The ground area (m²) sensor s (about N) sees from `height` above flat
// ground, its corner rays cut at 80° from the vertical.
double FootprintArea(const Pose6& s, double height, double focal_px, double image_size) {
  const Mat3 N_from_sensor = AngleAxisToRotation(Vec3(s[0], s[1], s[2])).transpose();
  const double c = image_size / 2, corners[4][2] = {{0, 0}, {image_size, 0},
                                                    {image_size, image_size}, {0, image_size}};
  double x[4], y[4];
  for (int k = 0; k < 4; ++k) {
    Vec3 d = N_from_sensor * Vec3((corners[k][0] - c) / focal_px, (corners[k][1] - c) / focal_px, 1.0);
    d.z() = std::max(d.z(), d.head<2>().norm() * std::cos(80.0 * kDegree));
    x[k] = height * d.x() / d.z(), y[k] = height * d.y() / d.z();
  }
  double area = 0.0;
  for (int k = 0; k < 4; ++k) area += x[k] * y[(k + 1) % 4] - x[(k + 1) % 4] * y[k];
  return 0.5 * std::abs(area);
}

// How far from the nadir point the footprint of s reaches.
double FootprintReach(const Pose6& s, double height, double focal_px, double image_size) {
  const Mat3 N_from_sensor = AngleAxisToRotation(Vec3(s[0], s[1], s[2])).transpose();
  double reach = 0.0;
  for (double u : {0.0, image_size}) {
    for (double v : {0.0, image_size}) {
      Vec3 d = N_from_sensor * Vec3((u - image_size / 2) / focal_px, (v - image_size / 2) / focal_px, 1.0);
      d.z() = std::max(d.z(), d.head<2>().norm() * std::cos(80.0 * kDegree));
      reach = std::max(reach, height * d.head<2>().norm() / d.z());
    }
  }
  return reach;
}

}  // namespace

int64_t RigSensorCount(const std::string& name) {
  return static_cast<int64_t>(NominalAboutNadir(name).size());
}

RigSensors MakeRigSensors(const std::string& name, uint64_t seed, double flying_height,
                          double focal_px, double image_size) {
  const std::vector<Pose6> about_nadir = NominalAboutNadir(name);
  std::mt19937_64 rng(seed ^ 0x7269677365ULL);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<Pose6> true_about_nadir = about_nadir;
  for (Pose6& s : true_about_nadir) {
    double delta[6];
    for (int k = 0; k < 3; ++k) delta[k] = 0.3 * kDegree * n01(rng);
    for (int k = 3; k < 6; ++k) delta[k] = 0.01 * n01(rng);
    PlusPose(s.data(), delta, s.data());
  }
  RigSensors r;
  r.nominal = AboutFirst(about_nadir);
  r.truth = AboutFirst(true_about_nadir);
  r.nominal_first = about_nadir[0];
  r.truth_first = true_about_nadir[0];
  const double nadir = FootprintArea(SensorPose(Mat3::Identity(), Vec3::Zero()), flying_height,
                                     focal_px, image_size);
  for (const Pose6& s : about_nadir) {
    r.keep.push_back(std::min(1.0, nadir / FootprintArea(s, flying_height, focal_px, image_size)));
    r.reach = std::max(r.reach, FootprintReach(s, flying_height, focal_px, image_size));
  }
  return r;
}

Problem RigCameraSide(const Problem& nadir, const std::vector<Pose6>& sensors, const Pose6& first) {
  const int64_t S = static_cast<int64_t>(sensors.size()), F = nadir.num_images();
  const int64_t G = nadir.num_groups();
  Problem p;
  p.model = CameraModel::kPhoto;
  p.intrinsics_size = nadir.intrinsics_size;
  if (!nadir.group_models.empty()) p.group_models.assign(S, nadir.group_models[0]);
  for (int64_t f = 0; f < F; ++f) {
    for (int64_t s = 0; s < S; ++s) {
      p.image_frame.push_back(static_cast<int32_t>(f));
      p.camera_intrinsics.push_back(static_cast<int32_t>(s));
    }
  }
  p.sensor_kind.assign(S, kSensorRefined);
  p.sensor_kind[0] = kRigOrigin;
  p.cameras.assign(kPhotoPoseSize * (F * S + F + S) + int64_t{p.intrinsics_size} * S, 0.0);
  for (int64_t s = 0; s < S; ++s) {
    std::copy_n(nadir.intrinsics(std::min(s, G - 1)), p.intrinsics_size, p.intrinsics(s));
    std::copy(sensors[s].begin(), sensors[s].end(), p.cameras.begin() + p.sensor_offset(s));
  }
  for (int64_t f = 0; f < F; ++f) {
    ComposeRigPose(first.data(), nadir.camera(f), p.cameras.data() + p.frame_offset(f));
  }
  ComposeRigImages(&p);
  return p;
}

}  // namespace dba
