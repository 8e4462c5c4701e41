// Robust losses of one observation and the Triggs correction that puts them
// into the Gauss-Newton model (Triggs et al., "Bundle adjustment — a modern
// synthesis", 2000, section 4.3; as Ceres's corrector.cc).
//
// The robust cost is ½ Σ_a ρ(s_a), s_a = |r_a|² the squared norm of an
// observation's 2D residual. With ρ' and ρ'' at s, the second-order model of
// ½ ρ(|r + J δ|²) is
//
//   ½ ρ(s) + ρ' rᵀJ δ + ½ δᵀ Jᵀ (ρ' I + 2 ρ'' r rᵀ) J δ.
//
// It equals the Gauss-Newton model ½ |r̃ + J̃ δ|² (up to a constant) of the
// corrected residual and Jacobian
//
//   r̃ = √ρ' / (1 - α) r,   J̃ = √ρ' (I - α r rᵀ / s) J,
//   α solving ½ α² - α - (ρ''/ρ') s = 0, i.e. α = 1 - √(1 + 2 s ρ''/ρ').
//
// Where ρ'' ≤ 0 (every loss below outside its quadratic zone) the curvature
// term would make the model indefinite and is dropped: α = 0, r̃ = √ρ' r,
// J̃ = √ρ' J. The corrected pair enters the RCS like any other observation,
// before the point is eliminated, so LM stays exact on the robust cost.
//
// Losses, for scale a (pixels), b = a², as Ceres defines them:
//   trivial  ρ = s
//   huber    ρ = s (s ≤ b), 2 a √s - b (s > b)
//   soft_l1  ρ = 2 b (√(1 + s/b) - 1)
//   cauchy   ρ = b log(1 + s/b)
//   arctan   ρ = a atan2(s, a)
//   tukey    ρ = b/3 (1 - (1 - s/b)³) (s ≤ b), b/3 (s > b)
//
// Thread safety: values; all functions pure.
#pragma once

#include <string>

#include "dba/camera/bal_camera.h"

namespace dba {

enum class LossType { kTrivial, kHuber, kSoftL1, kCauchy, kArctan, kTukey };
const char* LossName(LossType type);
// "trivial", "huber", "soft_l1", "cauchy", "arctan", "tukey".
bool ParseLoss(const std::string& name, LossType* type);

struct RobustLoss {
  LossType type = LossType::kTrivial;
  double scale = 1.0;  // a, pixels

  bool trivial() const { return type == LossType::kTrivial; }
  // rho[0..2] = ρ(s), ρ'(s), ρ''(s); s ≥ 0.
  void Evaluate(double s, double rho[3]) const;
  // ρ(s) alone.
  double Rho(double s) const;
  // An inlier for the RMS figures: |r| within the scale (every observation
  // for the squared loss).
  bool IsInlier(double s) const { return trivial() || s <= scale * scale; }
};

// The correction of one residual with squared norm s: an observation's 2D
// residual, or a prior's 3D one (lm/prior_workers.h).
class LossCorrection {
 public:
  LossCorrection(double s, const double rho[3]);
  // r̃ from r.
  template <class V>
  V Residual(const V& r) const { return residual_scaling_ * r; }
  // J̃ from J (|r| x n, any n), given the uncorrected residual r.
  template <class V, class Jacobian>
  void CorrectJacobian(const V& r, Jacobian* J) const {
    if (alpha_sq_norm_ == 0.0) {
      *J *= sqrt_rho1_;
      return;
    }
    const auto rJ = (r.transpose() * *J).eval();
    *J = sqrt_rho1_ * (*J - alpha_sq_norm_ * r * rJ);
  }

 private:
  double sqrt_rho1_ = 1.0;
  double residual_scaling_ = 1.0;
  double alpha_sq_norm_ = 0.0;  // α / s
};

}  // namespace dba
