// Pixel of a camera-frame point P = (Px, Py, Pz) under each lens model
// (problem/lens_model.h), with its analytic Jacobians. COLMAP's models follow
// COLMAP's ImgFromCam exactly (src/colmap/sensor/models.h); in its notation:
//
//   n = (Px, Py) / Pz                                 normalized coordinates
//   q = n θ / |n|,  θ = atan |n|                      fisheye models only
//                                                     (equidistant; q = n when
//                                                     |n| ≤ machine epsilon)
//   d = R(ρ²) q + t(q) + s(q),   ρ² = |q|²            polynomial distortion
//       R = (1 + a₁ρ² + a₂ρ⁴ + …) / (1 + b₁ρ² + b₂ρ⁴ + b₃ρ⁶)
//       t = (2p₁xy + p₂(ρ² + 2x²),  2p₂xy + p₁(ρ² + 2y²))   (OpenCV's order)
//       s = (sx₁ρ² + sx₂ρ⁴,  sy₁ρ² + sy₂ρ⁴)               (thin prism)
//   u = (fx d_x + cx,  fy d_y + cy)                   pixel (fx = fy = f for
//                                                     one-focal models)
//
//   SIMPLE_PINHOLE, PINHOLE, SIMPLE_FISHEYE, FISHEYE   d = n or q
//   SIMPLE_RADIAL, RADIAL                              a = (k) or (k1, k2)
//   OPENCV                                             a = (k1, k2), p
//   FULL_OPENCV                                        a = (k1, k2, k3), b = (k4, k5, k6), p
//   OPENCV_FISHEYE                                     on q, a = (k1, k2, k3, k4)
//   SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE              on q, a = (k) or (k1, k2)
//   THIN_PRISM_FISHEYE                                 on q, a = (k1..k4), p, sx₁, sy₁
//   RAD_TAN_THIN_PRISM_FISHEYE   two stages on q: y = (1 + k0θ² + … + k5θ¹²) q,
//                                then d = y + t(y) + s(y) with (p₁, p₂) = (p1, p0),
//                                (sx₁, sx₂, sy₁, sy₂) = (s0, s1, s2, s3)
//   radial-factor models, d = σ(|n|²) n:
//     FOV       σ = atan(2|n| tan(ω/2)) / (|n| ω), with COLMAP's series when
//               ω² < 1e-4 or |n|² < 1e-4
//     SIMPLE_DIVISION, DIVISION   σ = 2 / (1 + √(1 - 4k|n|²))   (Fitzgibbon)
//     EUCM      σ = 1 / (α √(β|n|² + 1) + 1 - α)
//   EQUIRECTANGULAR (w, h, never unknowns): spherical, on P itself:
//     u = (atan2(Px, Pz) / 2π + ½) w,   v = (½ - atan2(-Py, √(Px² + Pz²)) / π) h
//     (the residual jumps by w where a point crosses the seam behind the camera)
//
// dba's photogrammetric Brown–Conrady model (f, cx, cy, k1, k2, k3, p1, p2, b1,
// b2), in the same pixel convention as COLMAP (origin at the top-left corner,
// x right, y down, camera looking down +z):
//   d = (1 + k1ρ² + k2ρ⁴ + k3ρ⁶) n + t(n)          (OpenCV's p1, p2)
//   u = f d_x + b1 d_x + b2 d_y + cx,   v = f d_y + cy
// b1 (affinity) and b2 (shear) as Metashape defines them. Metashape's P1 and
// P2 are swapped against OpenCV's (and this model's): Metashape's P1 is p2.
//
// The perspective models, like today's photogrammetric camera, do not test
// that Pz > 0 (COLMAP's ImgFromCam refuses Pz < ε); the division model's
// square root of a negative number gives NaN where COLMAP refuses.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>

#include "dba/problem/lens_model.h"

namespace dba {

using LensPointJacobian = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;  // ∂u/∂P
// ∂u/∂params: the first num_params columns (the rest untouched).
using LensParamsJacobian = Eigen::Matrix<double, 2, kMaxIntrinsics, Eigen::RowMajor>;

// u(P) under model m with `params`; either Jacobian may be null.
Eigen::Vector2d LensProject(LensModel m, const double* params, const Eigen::Vector3d& P,
                            LensPointJacobian* du_dP, LensParamsJacobian* du_dparams);

namespace lens_internal {

// SIMPLE_PINHOLE, SIMPLE_RADIAL and RADIAL: how many radial terms (0, 1,
// 2), or -1 for any other model.
inline int OneFocalRadialTerms(LensModel m) {
  return m == LensModel::kSimplePinhole ? 0
         : m == LensModel::kSimpleRadial ? 1
         : m == LensModel::kRadial       ? 2
                                          : -1;
}

// Those three models (f, cx, cy[, k1[, k2]]: the paper's model and every
// shipped COLMAP model) written out and inline, where the generic path's
// loops, branches and calls cost 20% of back-substitution on fountain_p11
// (bench/README.md, "Camera models"):
//   d = 1 + k1 r² + k2 r⁴,  u = f d n + c,  ∂u/∂n = f (d I + 2 (k1 + 2 k2 r²) n nᵀ)
inline Eigen::Vector2d OneFocalRadial(int num_k, const double* k, const Eigen::Vector3d& P,
                                      LensPointJacobian* du_dP, LensParamsJacobian* J) {
  const double f = k[0], k1 = num_k > 0 ? k[3] : 0.0, k2 = num_k > 1 ? k[4] : 0.0;
  const double iz = 1.0 / P.z();
  const Eigen::Vector2d n(P.x() * iz, P.y() * iz);
  const double r2 = n.squaredNorm();
  const double d = 1.0 + r2 * (k1 + k2 * r2);
  if (du_dP != nullptr) {
    const Eigen::Matrix2d du_dn =
        f * (d * Eigen::Matrix2d::Identity() + 2.0 * (k1 + 2.0 * k2 * r2) * n * n.transpose());
    Eigen::Matrix<double, 2, 3> dn_dP;
    dn_dP << iz, 0.0, -n.x() * iz, 0.0, iz, -n.y() * iz;
    *du_dP = du_dn * dn_dP;
  }
  if (J != nullptr) {
    J->col(0) = d * n;
    J->col(1) = Eigen::Vector2d(1.0, 0.0);
    J->col(2) = Eigen::Vector2d(0.0, 1.0);
    if (num_k > 0) J->col(3) = f * r2 * n;
    if (num_k > 1) J->col(4) = f * r2 * r2 * n;
  }
  return Eigen::Vector2d(f * d * n.x() + k[1], f * d * n.y() + k[2]);
}

}  // namespace lens_internal

// LensProject with the three one-focal radial models inline (the kernels'
// call: no call into the generic path for them).
inline Eigen::Vector2d LensProjectInline(LensModel m, const double* params,
                                         const Eigen::Vector3d& P, LensPointJacobian* du_dP,
                                         LensParamsJacobian* du_dparams) {
  if (const int num_k = lens_internal::OneFocalRadialTerms(m); num_k >= 0) {
    return lens_internal::OneFocalRadial(num_k, params, P, du_dP, du_dparams);
  }
  return LensProject(m, params, P, du_dP, du_dparams);
}

}  // namespace dba
