// The BAL camera model and its analytic Jacobians (data/README.md):
//
//   P = R(ω) X + t,   p = -P.xy / P.z,   d = 1 + k1 |p|² + k2 |p|⁴,   u = f d p
//   residual r = u - u_observed
//
// Camera parameters c = (ω[3], t[3], f, k1, k2). R(ω) is the Rodrigues
// rotation of the angle-axis vector ω.
//
// Derivatives (chain rule):
//   ∂u/∂p = f (d I + 2 (k1 + 2 k2 |p|²) p pᵀ)
//   ∂p/∂P = [ -1/Pz   0    Px/Pz² ]
//           [   0   -1/Pz  Py/Pz² ]
//   ∂P/∂X = R,  ∂P/∂t = I,  ∂P/∂ω = -[R X]ₓ J_l(ω)
//   ∂u/∂f = d p,  ∂u/∂k1 = f |p|² p,  ∂u/∂k2 = f |p|⁴ p
// with the left Jacobian of SO(3)
//   J_l(ω) = I + (1 - cos θ)/θ² [ω]ₓ + (θ - sin θ)/θ³ [ω]ₓ²,  θ = |ω|.
//
// All functions are pure and thread-safe.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dba {

using Mat3 = Eigen::Matrix3d;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using CameraJacobian = Eigen::Matrix<double, 2, 9, Eigen::RowMajor>;
using PointJacobian = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// [v]ₓ, the matrix of the cross product: [v]ₓ w = v × w.
Mat3 SkewSymmetric(const Vec3& v);

// Rodrigues: rotation matrix of the angle-axis vector ω.
Mat3 AngleAxisToRotation(const Vec3& omega);

// Left Jacobian of SO(3): d(R(ω) X)/dω = -[R(ω) X]ₓ J_l(ω).
Mat3 SO3LeftJacobian(const Vec3& omega);

// R(ω) and J_l(ω) of one camera: the trigonometry of a camera, computed once
// for all its observations (a camera is seen by hundreds of points).
struct RotationFrame {
  Mat3 R;
  Mat3 J_l;
};
RotationFrame MakeRotationFrame(const double* omega);

// Residual of one observation; camera has 9 parameters, point 3.
Vec2 BalResidual(const double* camera, const double* point,
                 const double* observed);

// Residual and its Jacobians with respect to the camera and the point.
Vec2 BalResidualAndJacobians(const double* camera, const double* point,
                             const double* observed, CameraJacobian* J_c,
                             PointJacobian* J_p);
// The same with the camera's rotation frame given (MakeRotationFrame of its
// first 3 parameters).
Vec2 BalResidualAndJacobians(const RotationFrame& frame, const double* camera,
                             const double* point, const double* observed, CameraJacobian* J_c,
                             PointJacobian* J_p);

}  // namespace dba
