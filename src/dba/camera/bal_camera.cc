// BAL camera projection and analytic Jacobians; see bal_camera.h.
#include "dba/camera/bal_camera.h"

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
  // Written out in scalars (no 3x3 temporaries): this runs once per
  // observation in every formation and back-substitution.
  const double f = camera[6], k1 = camera[7], k2 = camera[8];
  const Mat3& R = frame.R;
  const double X0 = point[0], X1 = point[1], X2 = point[2];
  const double RX[3] = {R(0, 0) * X0 + R(0, 1) * X1 + R(0, 2) * X2,
                        R(1, 0) * X0 + R(1, 1) * X1 + R(1, 2) * X2,
                        R(2, 0) * X0 + R(2, 1) * X1 + R(2, 2) * X2};
  const double inv_z = 1.0 / (RX[2] + camera[5]);
  const double px = -(RX[0] + camera[3]) * inv_z, py = -(RX[1] + camera[4]) * inv_z;
  const double r2 = px * px + py * py;
  const double d = 1.0 + r2 * (k1 + k2 * r2);
  const Vec2 residual(f * d * px - observed[0], f * d * py - observed[1]);
  if (J_c == nullptr && J_p == nullptr) return residual;

  // ∂u/∂p = a I + c p pᵀ, and ∂p/∂P = inv_z [-1 0 -px; 0 -1 -py], so row i
  // of ∂u/∂P is inv_z (-q_i0, -q_i1, -(q_i0 px + q_i1 py)), q = ∂u/∂p.
  const double a = f * d, c = 2.0 * f * (k1 + 2.0 * k2 * r2);
  const double q[2][2] = {{a + c * px * px, c * px * py}, {c * px * py, a + c * py * py}};
  double du_dP[2][3];
  for (int i = 0; i < 2; ++i) {
    du_dP[i][0] = -inv_z * q[i][0];
    du_dP[i][1] = -inv_z * q[i][1];
    du_dP[i][2] = -inv_z * (q[i][0] * px + q[i][1] * py);
  }
  // Computed into locals, then stored: stores through J_c and J_p could
  // alias R and J_l as far as the compiler knows.
  if (J_c != nullptr) {
    const Mat3& L = frame.J_l;
    double Jc[2][9];
    for (int i = 0; i < 2; ++i) {
      // Row i of -∂u/∂P [RX]ₓ is RX × (∂u/∂P)_i; then times J_l.
      const double* v = du_dP[i];
      const double w[3] = {RX[1] * v[2] - RX[2] * v[1], RX[2] * v[0] - RX[0] * v[2],
                           RX[0] * v[1] - RX[1] * v[0]};
      for (int j = 0; j < 3; ++j) {
        Jc[i][j] = w[0] * L(0, j) + w[1] * L(1, j) + w[2] * L(2, j);
        Jc[i][3 + j] = v[j];
      }
    }
    const double p[2] = {px, py};
    for (int i = 0; i < 2; ++i) {
      Jc[i][6] = d * p[i];
      Jc[i][7] = f * r2 * p[i];
      Jc[i][8] = f * r2 * r2 * p[i];
    }
    *J_c = Eigen::Map<const BalCameraJacobian>(&Jc[0][0]);
  }
  if (J_p != nullptr) {
    double Jp[2][3];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 3; ++j) {
        Jp[i][j] = du_dP[i][0] * R(0, j) + du_dP[i][1] * R(1, j) + du_dP[i][2] * R(2, j);
      }
    }
    *J_p = Eigen::Map<const PointJacobian>(&Jp[0][0]);
  }
  return residual;
}

}  // namespace dba
