// The rig pose's composition against the camera-frame point it must give,
// and a residual's Jacobians in the frame's and the sensor's steps
// (camera/pose_step.h) against central differences.
#include "dba/camera/rig_pose.h"

#include <gtest/gtest.h>

#include <array>

#include "dba/camera/pose_step.h"

namespace dba {
namespace {

Vec3 CameraPoint(const double* pose, const Vec3& X) {
  return AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])) * X + Vec3(pose[3], pose[4], pose[5]);
}

TEST(RigPose, ComposedPoseMapsAsSensorAfterFrame) {
  const double sensor[6] = {0.1, -0.7, 0.2, 0.3, -0.05, 0.02};
  const double frame[6] = {2.5, 0.4, -1.1, 10.0, -3.0, 40.0};
  double image[6];
  ComposeRigPose(sensor, frame, image);
  for (const Vec3& X : {Vec3(1, 2, 3), Vec3(-40, 7, 0.5)}) {
    EXPECT_LT((CameraPoint(image, X) - CameraPoint(sensor, CameraPoint(frame, X))).norm(),
              1e-12 * (1 + X.norm()));
  }
  // The reference sensor (identity) leaves the frame's pose bit for bit.
  const double identity[6] = {0, 0, 0, 0, 0, 0};
  ComposeRigPose(identity, frame, image);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(image[k], frame[k]);
}

// r(frame ⊞ δ_f, sensor ⊞ δ_s) for the pinhole camera f = 800, c = (320, 240).
Vec2 Residual(const double* sensor, const double* frame, const Vec3& X) {
  double image[6];
  ComposeRigPose(sensor, frame, image);
  const double intrinsics[4] = {800, 810, 320, 240};
  const double observed[2] = {300, 200};
  return PhotoResidual(LensModel::kPinhole, image, intrinsics, X.data(), observed);
}

TEST(RigPose, ResidualJacobiansMatchCentralDifferencesOfTheSteps) {
  const std::array<std::array<double, 6>, 3> sensors = {{{0.1, -0.7, 0.2, 0.3, -0.05, 0.02},
                                                         {0, 0, 0, 0, 0, 0},
                                                         {1e-9, 2.9, -0.3, -1.0, 0.5, 0.25}}};
  const double frame0[6] = {2.5, 0.4, -1.1, 10.0, -3.0, 40.0};
  for (const auto& sensor0 : sensors) {
    double image[6];
    ComposeRigPose(sensor0.data(), frame0, image);
    // A point in front of the image: 30 units down its optical axis.
    const Mat3 R_i = AngleAxisToRotation(Vec3(image[0], image[1], image[2]));
    const Vec3 X = R_i.transpose() * (Vec3(1.0, -2.0, 30.0) - Vec3(image[3], image[4], image[5]));
    const double intrinsics[4] = {800, 810, 320, 240};
    const double observed[2] = {300, 200};
    PointJacobian J_X;
    PhotoResidualAndJacobians(LensModel::kPinhole, image, intrinsics, X.data(), observed, nullptr,
                              nullptr, &J_X);
    const RigChain chain = MakeRigChain(MakeRotationFrame(frame0),
                                        MakeRotationFrame(sensor0.data()), sensor0.data());
    PoseJacobian J_frame, J_sensor;
    const Vec3 P = R_i * X + Vec3(image[3], image[4], image[5]);
    RigResidualJacobians(chain, R_i, P, J_X, &J_frame, &J_sensor);
    for (int which = 0; which < 2; ++which) {
      for (int k = 0; k < 6; ++k) {
        const double h = 1e-6;
        Vec2 r[2];
        for (int side = 0; side < 2; ++side) {
          double delta[6] = {0, 0, 0, 0, 0, 0};
          delta[k] = side == 0 ? h : -h;
          double s[6], f[6];
          std::copy_n(sensor0.data(), 6, s);
          std::copy_n(frame0, 6, f);
          PlusPose(which == 0 ? f : s, delta, which == 0 ? f : s);
          r[side] = Residual(s, f, X);
        }
        const Vec2 numeric = (r[0] - r[1]) / (2 * h);
        const Vec2 analytic = which == 0 ? J_frame.col(k) : J_sensor.col(k);
        EXPECT_LT((numeric - analytic).norm(), 1e-6 * (1 + numeric.norm()))
            << (which == 0 ? "frame" : "sensor") << " column " << k << ": " << numeric.transpose()
            << " vs " << analytic.transpose();
      }
    }
  }
}

// With the rig's origin as sensor the frame's Jacobian is the image's own.
TEST(RigPose, OriginSensorGivesTheImagePoseJacobian) {
  const double origin[6] = {0, 0, 0, 0, 0, 0};
  const double frame[6] = {0.3, -0.2, 1.4, 5.0, 1.0, 20.0};
  const Mat3 R = AngleAxisToRotation(Vec3(frame[0], frame[1], frame[2]));
  const Vec3 X = R.transpose() * (Vec3(0.5, 0.7, 12.0) - Vec3(frame[3], frame[4], frame[5]));
  const double intrinsics[4] = {800, 810, 320, 240};
  const double observed[2] = {300, 200};
  PoseJacobian J_pose, J_frame;
  PointJacobian J_X;
  PhotoResidualAndJacobians(LensModel::kPinhole, frame, intrinsics, X.data(), observed, &J_pose,
                            nullptr, &J_X);
  RigResidualJacobians(MakeRigChain(MakeRotationFrame(frame), MakeRotationFrame(origin), origin), R,
                       R * X + Vec3(frame[3], frame[4], frame[5]), J_X, &J_frame, nullptr);
  EXPECT_LT((J_frame - J_pose).norm(), 1e-12 * J_pose.norm());
}

}  // namespace
}  // namespace dba
