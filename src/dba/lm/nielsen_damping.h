// The damping λ of Levenberg–Marquardt and its update after each step
// (Nielsen, "Damping parameter in Marquardt's method", IMM-REP-1999-05;
// Madsen, Nielsen & Tingleff, "Methods for non-linear least squares
// problems", 2004, eq. 2.21; docs/design.md §1.2):
//
//   accepted step with gain ratio ρ:  λ ← λ · max(1/3, 1 − (2ρ − 1)³),  ν ← 2
//   rejected step:                    λ ← λ · ν,                         ν ← 2ν
//
// A good step (ρ near 1) shrinks λ by up to 3, a poor accepted one grows it
// by up to 2; rejections grow it ever faster. λ never falls below a floor
// that the linear solver may set (DampedRcsSolver::min_lambda: a
// mixed-precision PCG's), 0 by default.
// Thread safety: a value.
#pragma once

#include <algorithm>

namespace dba {

class NielsenDamping {
 public:
  explicit NielsenDamping(double initial_lambda) : lambda_(initial_lambda) {}

  double lambda() const { return lambda_; }
  double nu() const { return nu_; }
  // From the next accepted step on, λ stays at or above `floor`.
  void SetFloor(double floor) { floor_ = floor; }

  void StepAccepted(double gain_ratio) {
    const double r = 2.0 * gain_ratio - 1.0;
    const double wanted = lambda_ * std::max(1.0 / 3.0, 1.0 - r * r * r);
    held_by_floor_ = wanted < floor_;
    lambda_ = std::max(floor_, wanted);
    nu_ = 2.0;
  }
  // Whether the last accepted step would have taken λ below the floor.
  bool held_by_floor() const { return held_by_floor_; }
  void StepRejected() {
    lambda_ *= nu_;
    nu_ *= 2.0;
  }

 private:
  double lambda_;
  double nu_ = 2.0;
  double floor_ = 0.0;
  bool held_by_floor_ = false;
};

}  // namespace dba
