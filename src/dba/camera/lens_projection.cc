// Lens projections and their analytic Jacobians; the equations are in
// lens_projection.h.
#include "dba/camera/lens_projection.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace dba {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using ParamsJ = LensParamsJacobian;

// n = P.xy / P.z and ∂n/∂P.
inline Vec2 Normalize(const Vec3& P, Mat23* dn_dP) {
  const double iz = 1.0 / P.z();
  const Vec2 n(P.x() * iz, P.y() * iz);
  if (dn_dP != nullptr) *dn_dP << iz, 0.0, -n.x() * iz, 0.0, iz, -n.y() * iz;
  return n;
}

// q = n atan(r) / r, r = |n|: the equidistant fisheye coordinates.
// ∂q/∂n = (θ/r) I + ((dσ/dr) / r) n nᵀ with σ = θ/r; near r = 0 the series
// of (dσ/dr)/r = (r/(1 + r²) - θ)/r³ avoids its cancellation.
inline Vec2 Equidistant(const Vec2& n, Mat2* dq_dn) {
  const double r2 = n.squaredNorm();
  const double r = std::sqrt(r2);
  if (r <= std::numeric_limits<double>::epsilon()) {
    if (dq_dn != nullptr) dq_dn->setIdentity();
    return n;
  }
  const double theta = std::atan(r);
  const double sigma = theta / r;
  if (dq_dn != nullptr) {
    const double dsigma_r = r < 1e-3 ? -2.0 / 3.0 + 0.8 * r2 - (6.0 / 7.0) * r2 * r2
                                     : (r / (1.0 + r2) - theta) / (r2 * r);
    *dq_dn = sigma * Mat2::Identity() + dsigma_r * n * n.transpose();
  }
  return sigma * n;
}

// Which parameters play the polynomial distortion's parts (-1: absent).
struct Polynomial {
  int na;
  int a[6];  // numerator a₁, a₂, …
  int nb;
  int b[3];  // denominator b₁, b₂, b₃
  int p1, p2, sx1, sx2, sy1, sy2;
};

// d = R(ρ²) q + t(q) + s(q) (header), ∂d/∂q, and ∂d/∂k into J's columns.
inline Vec2 Distort(const Polynomial& c, const double* k, const Vec2& q, Mat2* dd_dq,
                    ParamsJ* J) {
  const double x = q.x(), y = q.y(), r2 = x * x + y * y;
  double power[7];
  power[0] = 1.0;
  for (int i = 1; i <= std::max(c.na, c.nb); ++i) power[i] = power[i - 1] * r2;
  double N = 1.0, dN = 0.0;
  for (int i = 0; i < c.na; ++i) {
    N += k[c.a[i]] * power[i + 1];
    dN += (i + 1) * k[c.a[i]] * power[i];
  }
  double D = 1.0, dD = 0.0;
  for (int i = 0; i < c.nb; ++i) {
    D += k[c.b[i]] * power[i + 1];
    dD += (i + 1) * k[c.b[i]] * power[i];
  }
  const double R = N / D;
  const double dR = (dN * D - N * dD) / (D * D);
  Vec2 d = R * q;
  const double P1 = c.p1 >= 0 ? k[c.p1] : 0.0, P2 = c.p2 >= 0 ? k[c.p2] : 0.0;
  const double sx1 = c.sx1 >= 0 ? k[c.sx1] : 0.0, sx2 = c.sx2 >= 0 ? k[c.sx2] : 0.0;
  const double sy1 = c.sy1 >= 0 ? k[c.sy1] : 0.0, sy2 = c.sy2 >= 0 ? k[c.sy2] : 0.0;
  if (c.p1 >= 0) {
    d.x() += 2.0 * P1 * x * y + P2 * (r2 + 2.0 * x * x);
    d.y() += 2.0 * P2 * x * y + P1 * (r2 + 2.0 * y * y);
  }
  if (c.sx1 >= 0) {
    d.x() += (sx1 + sx2 * r2) * r2;
    d.y() += (sy1 + sy2 * r2) * r2;
  }
  if (dd_dq != nullptr) {
    *dd_dq = R * Mat2::Identity() + 2.0 * dR * q * q.transpose();
    if (c.p1 >= 0) {
      (*dd_dq)(0, 0) += 2.0 * P1 * y + 6.0 * P2 * x;
      (*dd_dq)(0, 1) += 2.0 * P1 * x + 2.0 * P2 * y;
      (*dd_dq)(1, 0) += 2.0 * P2 * y + 2.0 * P1 * x;
      (*dd_dq)(1, 1) += 2.0 * P2 * x + 6.0 * P1 * y;
    }
    if (c.sx1 >= 0) {
      dd_dq->row(0) += 2.0 * (sx1 + 2.0 * sx2 * r2) * q.transpose();
      dd_dq->row(1) += 2.0 * (sy1 + 2.0 * sy2 * r2) * q.transpose();
    }
  }
  if (J != nullptr) {
    for (int i = 0; i < c.na; ++i) J->col(c.a[i]) = (power[i + 1] / D) * q;
    for (int i = 0; i < c.nb; ++i) J->col(c.b[i]) = (-R * power[i + 1] / D) * q;
    if (c.p1 >= 0) {
      J->col(c.p1) = Vec2(2.0 * x * y, r2 + 2.0 * y * y);
      J->col(c.p2) = Vec2(r2 + 2.0 * x * x, 2.0 * x * y);
    }
    if (c.sx1 >= 0) {
      J->col(c.sx1) = Vec2(r2, 0.0);
      J->col(c.sy1) = Vec2(0.0, r2);
      if (c.sx2 >= 0) J->col(c.sx2) = Vec2(r2 * r2, 0.0);
      if (c.sy2 >= 0) J->col(c.sy2) = Vec2(0.0, r2 * r2);
    }
  }
  return d;
}

// σ(ρ²) of a radial-factor model, with dσ/dρ² and dσ/d(its parameters).
struct Factor {
  double sigma, dsigma_dr2, dsigma_dk[2];
};

// FOV (Devernay–Faugeras), COLMAP's three branches.
Factor FovFactor(double omega, double r2) {
  constexpr double kEpsilon = 1e-4;
  const double w2 = omega * omega;
  if (w2 < kEpsilon) {
    return {w2 * r2 / 3.0 - w2 / 12.0 + 1.0, w2 / 3.0, {2.0 * omega * r2 / 3.0 - omega / 6.0, 0}};
  }
  const double t = std::tan(omega / 2.0);
  const double dt = 0.5 * (1.0 + t * t);  // dt/dω
  if (r2 < kEpsilon) {
    // σ = (6t - 8ρ²t³) / (3ω)
    const double num = 6.0 * t - 8.0 * r2 * t * t * t;
    const double dnum = (6.0 - 24.0 * r2 * t * t) * dt;
    return {num / (3.0 * omega), -8.0 * t * t * t / (3.0 * omega),
            {(dnum * omega - num) / (3.0 * omega * omega), 0}};
  }
  const double r = std::sqrt(r2);
  const double A = std::atan(2.0 * r * t);
  const double dA_common = 1.0 / (1.0 + 4.0 * r2 * t * t);
  const double dA_dr = 2.0 * t * dA_common, dA_dw = 2.0 * r * dt * dA_common;
  const double sigma = A / (r * omega);
  const double dsigma_dr = (dA_dr * r - A) / (r2 * omega);
  return {sigma, dsigma_dr / (2.0 * r), {(dA_dw * omega - A) / (r * omega * omega), 0}};
}

// Division (Fitzgibbon): σ = 2 / (1 + Q), Q = √(1 - 4kρ²).
Factor DivisionFactor(double k, double r2) {
  const double Q = std::sqrt(1.0 - 4.0 * k * r2);
  const double dsigma_dQ = -2.0 / ((1.0 + Q) * (1.0 + Q));
  return {2.0 / (1.0 + Q), dsigma_dQ * (-2.0 * k / Q), {dsigma_dQ * (-2.0 * r2 / Q), 0}};
}

// EUCM: σ = 1 / (α S + 1 - α), S = √(βρ² + 1).
Factor EucmFactor(double alpha, double beta, double r2) {
  const double S = std::sqrt(beta * r2 + 1.0);
  const double den = alpha * S + 1.0 - alpha;
  const double m = -1.0 / (den * den);
  return {1.0 / den, m * alpha * beta / (2.0 * S), {m * (S - 1.0), m * alpha * r2 / (2.0 * S)}};
}

// d = σ(|n|²) n.
inline Vec2 ApplyFactor(const Factor& f, const Vec2& n, const int* index, int count,
                        Mat2* dd_dn, ParamsJ* J) {
  if (dd_dn != nullptr) {
    *dd_dn = f.sigma * Mat2::Identity() + 2.0 * f.dsigma_dr2 * n * n.transpose();
  }
  if (J != nullptr) {
    for (int i = 0; i < count; ++i) J->col(index[i]) = f.dsigma_dk[i] * n;
  }
  return f.sigma * n;
}

// EQUIRECTANGULAR (header): θ = atan2(Px, Pz), φ = atan2(-Py, h), h = √(Px² + Pz²).
Vec2 Equirectangular(const double* k, const Vec3& P, LensPointJacobian* du_dP, ParamsJ* J) {
  constexpr double kPi = std::numbers::pi;
  const double w = k[0], hgt = k[1];
  const double h2 = P.x() * P.x() + P.z() * P.z();
  const double h = std::sqrt(h2);
  const double theta = std::atan2(P.x(), P.z());
  const double phi = std::atan2(-P.y(), h);
  const Vec2 u((theta / (2.0 * kPi) + 0.5) * w, (0.5 - phi / kPi) * hgt);
  if (du_dP != nullptr) {
    const double n2 = h2 + P.y() * P.y();
    const Eigen::RowVector3d dtheta(P.z() / h2, 0.0, -P.x() / h2);
    const Eigen::RowVector3d dphi(P.y() * P.x() / (h * n2), -h / n2, P.y() * P.z() / (h * n2));
    du_dP->row(0) = (w / (2.0 * kPi)) * dtheta;
    du_dP->row(1) = (-hgt / kPi) * dphi;
  }
  if (J != nullptr) {
    J->col(0) = Vec2(theta / (2.0 * kPi) + 0.5, 0.0);
    J->col(1) = Vec2(0.0, 0.5 - phi / kPi);
  }
  return u;
}

constexpr Polynomial kNoPolynomial{0, {}, 0, {}, -1, -1, -1, -1, -1, -1};
constexpr Polynomial Radial1(int k) { return {1, {k}, 0, {}, -1, -1, -1, -1, -1, -1}; }
constexpr Polynomial Radial2(int k) { return {2, {k, k + 1}, 0, {}, -1, -1, -1, -1, -1, -1}; }

// Brown's affine image axes: u = A d + c, A = [f + b1, b2; 0, f], d the
// radial-tangential distortion of n.
Vec2 BrownProject(const double* k, const Vec2& n, const Mat23* dn_dP, LensPointJacobian* du_dP,
                  ParamsJ* J) {
  Mat2 dd_dn;
  const Vec2 d = Distort({3, {3, 4, 5}, 0, {}, 6, 7, -1, -1, -1, -1}, k, n,
                         du_dP != nullptr ? &dd_dn : nullptr, J);
  const double f = k[0], b1 = k[8], b2 = k[9];
  Mat2 A;
  A << f + b1, b2, 0.0, f;
  if (du_dP != nullptr) *du_dP = A * dd_dn * *dn_dP;
  if (J != nullptr) {
    J->middleCols<5>(3) = A * J->middleCols<5>(3);
    J->col(0) = d;
    J->col(1) = Vec2(1.0, 0.0);
    J->col(2) = Vec2(0.0, 1.0);
    J->col(8) = Vec2(d.x(), 0.0);
    J->col(9) = Vec2(d.y(), 0.0);
  }
  return A * d + Vec2(k[1], k[2]);
}

// The distorted normalized point d of the normalized point n, for the
// models with focal lengths and a principal point applied after
// (FocalAndCentre); dd_dn where asked, the distortion parameters' columns of
// J. `two_focal`: whether the layout is (fx, fy, cx, cy, extras from 4)
// rather than (f, cx, cy, extras from 3).
Vec2 DistortNormalized(LensModel m, const double* k, const Vec2& n, Mat2* dd_dn, ParamsJ* J,
                       bool* two_focal) {
  const bool want_dP = dd_dn != nullptr;
  *two_focal = true;
  auto on_q = [&](const Polynomial& c) {  // fisheye: the polynomial acts on q
    Mat2 dq_dn;
    const Vec2 q = Equidistant(n, want_dP ? &dq_dn : nullptr);
    Mat2 dd_dq;
    const Vec2 out = Distort(c, k, q, want_dP ? &dd_dq : nullptr, J);
    if (want_dP) *dd_dn = dd_dq * dq_dn;
    return out;
  };
  switch (m) {
    case LensModel::kPinhole:
      if (want_dP) dd_dn->setIdentity();
      return n;
    case LensModel::kOpenCV: return Distort({2, {4, 5}, 0, {}, 6, 7, -1, -1, -1, -1}, k, n, dd_dn, J);
    case LensModel::kFullOpenCV:
      return Distort({3, {4, 5, 8}, 3, {9, 10, 11}, 6, 7, -1, -1, -1, -1}, k, n, dd_dn, J);
    case LensModel::kOpenCVFisheye: return on_q({4, {4, 5, 6, 7}, 0, {}, -1, -1, -1, -1, -1, -1});
    case LensModel::kSimpleRadialFisheye: *two_focal = false; return on_q(Radial1(3));
    case LensModel::kRadialFisheye: *two_focal = false; return on_q(Radial2(3));
    case LensModel::kThinPrismFisheye: return on_q({4, {4, 5, 8, 9}, 0, {}, 6, 7, 10, -1, 11, -1});
    case LensModel::kRadTanThinPrismFisheye: {
      // Two stages: y = R(θ²) q, then d = y + t(y) + s(y).
      Mat2 dy_dn;
      ParamsJ J_radial;
      const Vec2 y = [&] {
        Mat2 dq_dn, dy_dq;
        const Vec2 q = Equidistant(n, want_dP ? &dq_dn : nullptr);
        const Vec2 out = Distort({6, {4, 5, 6, 7, 8, 9}, 0, {}, -1, -1, -1, -1, -1, -1}, k, q,
                                 want_dP ? &dy_dq : nullptr, J != nullptr ? &J_radial : nullptr);
        if (want_dP) dy_dn = dy_dq * dq_dn;
        return out;
      }();
      Mat2 dd_dy;
      const Vec2 d = Distort({0, {}, 0, {}, 11, 10, 12, 13, 14, 15}, k, y, &dd_dy, J);
      if (want_dP) *dd_dn = dd_dy * dy_dn;
      if (J != nullptr) J->middleCols<6>(4) = dd_dy * J_radial.middleCols<6>(4);
      return d;
    }
    case LensModel::kFov: {
      const int index[1] = {4};
      return ApplyFactor(FovFactor(k[4], n.squaredNorm()), n, index, 1, dd_dn, J);
    }
    case LensModel::kSimpleDivision:
      *two_focal = false;
      [[fallthrough]];
    case LensModel::kDivision: {
      const int index[1] = {*two_focal ? 4 : 3};
      return ApplyFactor(DivisionFactor(k[index[0]], n.squaredNorm()), n, index, 1, dd_dn, J);
    }
    case LensModel::kSimpleFisheye:
      *two_focal = false;
      [[fallthrough]];
    case LensModel::kFisheye: return on_q(kNoPolynomial);
    case LensModel::kEucm: {
      const int index[2] = {4, 5};
      return ApplyFactor(EucmFactor(k[4], k[5], n.squaredNorm()), n, index, 2, dd_dn, J);
    }
    case LensModel::kBrown:  // BrownProject
    case LensModel::kSimplePinhole:
    case LensModel::kSimpleRadial:
    case LensModel::kRadial:
    case LensModel::kEquirectangular:
      break;  // handled by LensProject before
  }
  return n;
}

// u = (fx dx + cx, fy dy + cy) of the distorted normalized point d, with
// du/dP and the focal lengths' and principal point's columns of J (the
// distortion's columns scaled by the focal lengths).
Vec2 FocalAndCentre(LensModel m, const double* k, const Vec2& d, bool two_focal,
                    const Mat2* dd_dn, const Mat23* dn_dP, LensPointJacobian* du_dP, ParamsJ* J) {
  const int first_extra = two_focal ? 4 : 3;
  const double fx = k[0], fy = two_focal ? k[1] : k[0];
  const double cx = k[first_extra - 2], cy = k[first_extra - 1];
  if (du_dP != nullptr) {
    Mat2 du_dn = *dd_dn;
    du_dn.row(0) *= fx;
    du_dn.row(1) *= fy;
    *du_dP = du_dn * *dn_dP;
  }
  if (J != nullptr) {
    const int count = LensModelParams(m);
    for (int j = first_extra; j < count; ++j) {
      (*J)(0, j) *= fx;
      (*J)(1, j) *= fy;
    }
    if (two_focal) {
      J->col(0) = Vec2(d.x(), 0.0);
      J->col(1) = Vec2(0.0, d.y());
    } else {
      J->col(0) = d;
    }
    J->col(first_extra - 2) = Vec2(1.0, 0.0);
    J->col(first_extra - 1) = Vec2(0.0, 1.0);
  }
  return Vec2(fx * d.x() + cx, fy * d.y() + cy);
}

}  // namespace

Vec2 LensProject(LensModel m, const double* k, const Vec3& P, LensPointJacobian* du_dP,
                 ParamsJ* J) {
  if (const int num_k = lens_internal::OneFocalRadialTerms(m); num_k >= 0) {
    return lens_internal::OneFocalRadial(num_k, k, P, du_dP, J);
  }
  if (m == LensModel::kEquirectangular) return Equirectangular(k, P, du_dP, J);
  const bool want_dP = du_dP != nullptr;
  Mat23 dn_dP;
  const Vec2 n = Normalize(P, want_dP ? &dn_dP : nullptr);
  if (m == LensModel::kBrown) return BrownProject(k, n, &dn_dP, du_dP, J);
  Mat2 dd_dn;
  bool two_focal = true;
  const Vec2 d = DistortNormalized(m, k, n, want_dP ? &dd_dn : nullptr, J, &two_focal);
  return FocalAndCentre(m, k, d, two_focal, &dd_dn, &dn_dP, du_dP, J);
}

}  // namespace dba
