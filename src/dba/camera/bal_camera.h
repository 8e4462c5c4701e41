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
//   ∂P/∂X = R,  ∂P/∂δC = -R,  ∂P/∂δω = -[P]ₓ J_l(ω)
//   ∂u/∂f = d p,  ∂u/∂k1 = f |p|² p,  ∂u/∂k2 = f |p|⁴ p
// with J_l the left Jacobian of SO(3) (camera/rotation.h). The pose's
// columns are on its step (δω, δC) of camera/pose_step.h, not on (ω, t):
// J_c's columns are ∂r/∂(δω, δC, f, k1, k2).
//
// All functions are pure and thread-safe.
#pragma once

#include "dba/camera/rotation.h"

namespace dba {

// Residual of one observation; camera has 9 parameters, point 3.
Vec2 BalResidual(const double* camera, const double* point,
                 const double* observed);

// Residual and its Jacobians with respect to the camera and the point.
Vec2 BalResidualAndJacobians(const double* camera, const double* point,
                             const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p);
// The same with the camera's rotation frame given (MakeRotationFrame of its
// first 3 parameters).
Vec2 BalResidualAndJacobians(const RotationFrame& frame, const double* camera,
                             const double* point, const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p);

}  // namespace dba
