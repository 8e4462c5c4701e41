// BAL camera projection and analytic Jacobians; see bal_camera.h.
#include "dba/camera/bal_camera.h"

#include "dba/camera/bal_kernel.h"

#include <cmath>

namespace dba {

Vec2 BalResidual(const double* camera, const double* point,
                 const double* observed) {
  const Vec3 omega(camera[0], camera[1], camera[2]);
  const Vec3 t(camera[3], camera[4], camera[5]);
  const Vec3 P = AngleAxisToRotation(omega) * Vec3(point[0], point[1], point[2]) + t;
  const Vec2 p(-P.x() / P.z(), -P.y() / P.z());
  const double r2 = p.squaredNorm();
  const double d = 1.0 + r2 * (camera[7] + camera[8] * r2);
  return camera[6] * d * p - Vec2(observed[0], observed[1]);
}

Vec2 BalResidualAndJacobians(const double* camera, const double* point,
                             const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p) {
  return BalResidualAndJacobians(MakeRotationFrame(camera), camera, point, observed, J_c, J_p);
}

Vec2 BalResidualAndJacobians(const RotationFrame& frame, const double* camera,
                             const double* point, const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p) {
  double R[9], L[9];
  for (int e = 0; e < 9; ++e) R[e] = frame.R.data()[e], L[e] = frame.J_l.data()[e];
  const double t[3] = {camera[3], camera[4], camera[5]};
  const double u[2] = {observed[0], observed[1]};
  double r[2], Jc[2][9], Jp[2][3];
  const bool jacobians = J_c != nullptr || J_p != nullptr;
  BalKernel(R, L, t, camera[6], camera[7], camera[8], u, point, r, jacobians ? Jc : nullptr, Jp);
  if (J_c != nullptr) *J_c = Eigen::Map<const BalCameraJacobian>(&Jc[0][0]);
  if (J_p != nullptr) *J_p = Eigen::Map<const PointJacobian>(&Jp[0][0]);
  return Vec2(r[0], r[1]);
}

}  // namespace dba
