// Rotations by angle-axis vectors, shared by both camera models
// (docs/design.md §6):
//
//   R(ω) = I + (sin θ / θ) [ω]ₓ + ((1 - cos θ) / θ²) [ω]ₓ²      (Rodrigues)
//   J_l(ω) = I + ((1 - cos θ) / θ²) [ω]ₓ + ((θ - sin θ) / θ³) [ω]ₓ²,   θ = |ω|
//
// J_l is the left Jacobian of SO(3): stepping ω additively,
// ∂(R(ω) X)/∂ω = -[R(ω) X]ₓ J_l(ω). Near θ = 0 both use Taylor series.
// Also the small fixed-size types of the camera models.
//
// All functions are pure and thread-safe.
#pragma once

#include <Eigen/Core>

namespace dba {

using Mat3 = Eigen::Matrix3d;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
// ∂r/∂X of one observation, in either model.
using PointJacobian = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
// ∂r/∂c of one observation of a BAL camera (9 parameters).
using BalCameraJacobian = Eigen::Matrix<double, 2, 9, Eigen::RowMajor>;

// [v]ₓ, the matrix of the cross product: [v]ₓ w = v × w.
Mat3 SkewSymmetric(const Vec3& v);

// Rodrigues: the rotation matrix of the angle-axis vector ω.
Mat3 AngleAxisToRotation(const Vec3& omega);

// The left Jacobian of SO(3) at ω.
Mat3 SO3LeftJacobian(const Vec3& omega);

// R(ω) and J_l(ω) of one camera: its trigonometry, computed once for all its
// observations (a camera is seen by hundreds of points).
struct RotationFrame {
  Mat3 R;
  Mat3 J_l;
};
RotationFrame MakeRotationFrame(const double* omega);

}  // namespace dba
