// The rig pose's composition against the camera-frame point it must give,
// and its Jacobians against central differences.
#include "dba/camera/rig_pose.h"

#include <gtest/gtest.h>

#include <array>

namespace dba {
namespace {

Vec3 CameraPoint(const double* pose, const Vec3& X) {
  return AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])) * X + Vec3(pose[3], pose[4], pose[5]);
}

Vec3 RigCameraPoint(const double* sensor, const double* frame, const Vec3& X) {
  return CameraPoint(sensor, CameraPoint(frame, X));
}

TEST(RigPose, ComposedPoseMapsAsSensorAfterFrame) {
  const double sensor[6] = {0.1, -0.7, 0.2, 0.3, -0.05, 0.02};
  const double frame[6] = {2.5, 0.4, -1.1, 10.0, -3.0, 40.0};
  double image[6];
  ComposeRigPose(sensor, frame, image);
  for (const Vec3& X : {Vec3(1, 2, 3), Vec3(-40, 7, 0.5)}) {
    EXPECT_LT((CameraPoint(image, X) - RigCameraPoint(sensor, frame, X)).norm(), 1e-12 * (1 + X.norm()));
  }
  // The reference sensor (identity) leaves the frame's pose.
  const double identity[6] = {0, 0, 0, 0, 0, 0};
  ComposeRigPose(identity, frame, image);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(image[k], frame[k], 1e-14 * (1 + std::abs(frame[k])));
}

TEST(RigPose, JacobiansMatchCentralDifferences) {
  const std::array<std::array<double, 6>, 3> sensors = {{{0.1, -0.7, 0.2, 0.3, -0.05, 0.02},
                                                         {0, 0, 0, 0, 0, 0},
                                                         {1e-9, 2.9, -0.3, -1.0, 0.5, 0.25}}};
  const double frame0[6] = {2.5, 0.4, -1.1, 10.0, -3.0, 40.0};
  const Vec3 X(3.0, -2.0, 25.0);
  for (const auto& sensor0 : sensors) {
    const RigPoseJacobians J = RigCameraPointJacobians(sensor0.data(), frame0, X);
    for (int which = 0; which < 2; ++which) {
      for (int k = 0; k < 6; ++k) {
        double s[6], f[6];
        std::copy_n(sensor0.data(), 6, s);
        std::copy_n(frame0, 6, f);
        double* p = which == 0 ? f : s;
        const double h = 1e-6;
        p[k] += h;
        const Vec3 plus = RigCameraPoint(s, f, X);
        p[k] -= 2 * h;
        const Vec3 minus = RigCameraPoint(s, f, X);
        const Vec3 numeric = (plus - minus) / (2 * h);
        const Vec3 analytic = which == 0 ? J.frame.col(k) : J.sensor.col(k);
        EXPECT_LT((numeric - analytic).norm(), 1e-6 * (1 + numeric.norm()))
            << (which == 0 ? "frame" : "sensor") << " column " << k << ": " << numeric.transpose()
            << " vs " << analytic.transpose();
      }
    }
  }
}

}  // namespace
}  // namespace dba
