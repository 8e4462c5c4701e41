// Robust losses and the Triggs correction; see robust_loss.h.
#include "dba/rcs/robust_loss.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dba {

const char* LossName(LossType type) {
  switch (type) {
    case LossType::kTrivial: return "trivial";
    case LossType::kHuber: return "huber";
    case LossType::kSoftL1: return "soft_l1";
    case LossType::kCauchy: return "cauchy";
    case LossType::kArctan: return "arctan";
    case LossType::kTukey: return "tukey";
  }
  return "unknown";
}

bool ParseLoss(const std::string& name, LossType* type) {
  for (LossType t : {LossType::kTrivial, LossType::kHuber, LossType::kSoftL1, LossType::kCauchy,
                     LossType::kArctan, LossType::kTukey}) {
    if (name == LossName(t)) {
      *type = t;
      return true;
    }
  }
  return false;
}

void RobustLoss::Evaluate(double s, double rho[3]) const {
  constexpr double kTiny = std::numeric_limits<double>::min();  // ρ' stays > 0
  const double a = scale, b = scale * scale;
  switch (type) {
    case LossType::kTrivial:
      rho[0] = s, rho[1] = 1.0, rho[2] = 0.0;
      return;
    case LossType::kHuber:
      if (s > b) {
        const double r = std::sqrt(s);
        rho[0] = 2.0 * a * r - b;
        rho[1] = std::max(kTiny, a / r);
        rho[2] = -rho[1] / (2.0 * s);
      } else {
        rho[0] = s, rho[1] = 1.0, rho[2] = 0.0;
      }
      return;
    case LossType::kSoftL1: {
      const double sum = 1.0 + s / b, root = std::sqrt(sum);
      rho[0] = 2.0 * b * (root - 1.0);
      rho[1] = std::max(kTiny, 1.0 / root);
      rho[2] = -rho[1] / (2.0 * b * sum);
      return;
    }
    case LossType::kCauchy: {
      const double sum = 1.0 + s / b, inverse = 1.0 / sum;
      rho[0] = b * std::log(sum);
      rho[1] = std::max(kTiny, inverse);
      rho[2] = -inverse * inverse / b;
      return;
    }
    case LossType::kArctan: {
      const double inverse = 1.0 / (1.0 + s * s / b);
      rho[0] = a * std::atan2(s, a);
      rho[1] = std::max(kTiny, inverse);
      rho[2] = -2.0 * s / b * inverse * inverse;
      return;
    }
    case LossType::kTukey:
      if (s <= b) {
        const double v = 1.0 - s / b;
        rho[0] = b / 3.0 * (1.0 - v * v * v);
        rho[1] = v * v;
        rho[2] = -2.0 / b * v;
      } else {
        rho[0] = b / 3.0, rho[1] = 0.0, rho[2] = 0.0;
      }
      return;
  }
}

double RobustLoss::Rho(double s) const {
  if (type == LossType::kTrivial) return s;
  double rho[3];
  Evaluate(s, rho);
  return rho[0];
}

LossCorrection::LossCorrection(double s, const double rho[3]) {
  sqrt_rho1_ = std::sqrt(rho[1]);
  residual_scaling_ = sqrt_rho1_;
  if (s == 0.0 || rho[2] <= 0.0) return;  // α = 0: the curvature term dropped
  const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
  residual_scaling_ = sqrt_rho1_ / (1.0 - alpha);
  alpha_sq_norm_ = alpha / s;
}

}  // namespace dba
