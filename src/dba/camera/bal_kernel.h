// The BAL projection and its Jacobians (camera/bal_camera.h gives the
// formulas) written once for any arithmetic type T: double for one
// observation (camera/bal_camera.cc), a vector of four doubles for four
// observations in SIMD lanes (camera/bal_camera_lanes.cc). T needs +, -, *,
// / and mixing with double scalars.
//
// R and L are R(ω) and J_l(ω) column-major (R(i, j) = R[i + 3 j]); t the
// translation; u the observed pixel. Writes the residual r and, when J_c is
// not null, ∂r/∂c (2 x 9, on the pose's step (δω, δC), then f, k1, k2) and
// ∂r/∂X (2 x 3).
// Thread safety: pure.
#pragma once

namespace dba {

template <class T>
inline void BalKernel(const T (&R)[9], const T (&L)[9], const T (&t)[3], T f, T k1, T k2,
                      const T (&u)[2], const double* X, T (&r)[2], T (*J_c)[9], T (*J_p)[3]) {
  const double X0 = X[0], X1 = X[1], X2 = X[2];
  const T RX[3] = {R[0] * X0 + R[3] * X1 + R[6] * X2, R[1] * X0 + R[4] * X1 + R[7] * X2,
                   R[2] * X0 + R[5] * X1 + R[8] * X2};
  const T P[3] = {RX[0] + t[0], RX[1] + t[1], RX[2] + t[2]};
  const T inv_z = 1.0 / P[2];
  const T px = -P[0] * inv_z, py = -P[1] * inv_z;
  const T r2 = px * px + py * py;
  const T d = 1.0 + r2 * (k1 + k2 * r2);
  r[0] = f * d * px - u[0];
  r[1] = f * d * py - u[1];
  if (J_c == nullptr) return;

  // ∂u/∂p = a I + c p pᵀ, and ∂p/∂P = inv_z [-1 0 -px; 0 -1 -py], so row i
  // of ∂u/∂P is -inv_z (q_i0, q_i1, q_i0 px + q_i1 py), q = ∂u/∂p.
  const T a = f * d, c = 2.0 * f * (k1 + 2.0 * k2 * r2);
  const T q01 = c * px * py;
  const T q[2][2] = {{a + c * px * px, q01}, {q01, a + c * py * py}};
  const T p[2] = {px, py};
  for (int i = 0; i < 2; ++i) {
    const T v[3] = {-inv_z * q[i][0], -inv_z * q[i][1], -inv_z * (q[i][0] * px + q[i][1] * py)};
    // Row i of -∂u/∂P [P]ₓ is P × (∂u/∂P)_i; then times J_l. The centre's
    // columns are minus the point's (camera/pose_step.h).
    const T w[3] = {P[1] * v[2] - P[2] * v[1], P[2] * v[0] - P[0] * v[2],
                    P[0] * v[1] - P[1] * v[0]};
    for (int j = 0; j < 3; ++j) {
      J_c[i][j] = w[0] * L[3 * j] + w[1] * L[3 * j + 1] + w[2] * L[3 * j + 2];
      J_p[i][j] = v[0] * R[3 * j] + v[1] * R[3 * j + 1] + v[2] * R[3 * j + 2];
      J_c[i][3 + j] = -J_p[i][j];
    }
    J_c[i][6] = d * p[i];
    J_c[i][7] = f * r2 * p[i];
    J_c[i][8] = J_c[i][7] * r2;
  }
}

}  // namespace dba
