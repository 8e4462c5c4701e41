// Preconditioned conjugate gradients for S y = b (paper eq. 6-7), S symmetric
// positive definite in BSMC, with a preconditioner M ≈ S:
//
//   r0 = b - S y0, z0 = M⁻¹ r0, d0 = z0
//   α_k = r_kᵀ z_k / d_kᵀ S d_k,  y += α d,  r -= α S d
//   z = M⁻¹ r,  β = r_{k+1}ᵀ z_{k+1} / r_kᵀ z_k,  d = z + β d
//
// Inside Levenberg-Marquardt the linear system only has to be solved well
// enough for the step to lower the model: the truncated-Newton stop of Nash
// and Sofer ("Assessing a search direction within a truncated-Newton method",
// Operations Research Letters 9, 1990) ends PCG at iteration i when the
// quadratic model Q(y) = ½ yᵀS y - bᵀy = -½ yᵀ(b + r) stops improving:
//
//   i · (Q_i - Q_{i-1}) / Q_i < η.
//
// A relative-residual test ‖r‖ ≤ tol ‖b‖ is kept as a second stop (for tight
// solves), and the iteration cap only as a safety net. The recurrence for r
// drifts from b - S y in floating point; it is recomputed every
// `residual_reset_period` iterations.
//
// Thread safety: one solve at a time per scratch and multiplier.
#pragma once

#include <string>
#include <vector>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/solver/preconditioner.h"

namespace dba {

// The precision of S in PCG's product (bsmc/symmetric_multiply.h): auto is
// mixed (off-diagonal blocks in float, half the bytes of the product) while
// the η stop is on, which never sees float's rounding of S (6e-8 relative
// per value, far inside η), and double for a tight solve (η = 0).
enum class PcgPrecision { kAuto, kMixed, kDouble };
const char* PcgPrecisionName(PcgPrecision precision);
// "auto", "mixed", "double"; false if `name` is none of them.
bool ParsePcgPrecision(const std::string& name, PcgPrecision* precision);

struct PcgOptions {
  // Nash-Sofer stop; 0 turns it off (the residual test alone decides).
  // 0.1 by measurement (bench/README.md, "Linear solvers"), as Ceres.
  double eta = 0.1;
  // Stop when ‖b - S y‖ ≤ relative_tolerance · ‖b‖.
  double relative_tolerance = 1e-10;
  // The Nash-Sofer test is not taken before this many iterations: with a
  // strong preconditioner the first few can lower Q by most of what the
  // solve will and then stall briefly, and a step cut there is little better
  // than a preconditioned gradient step (see SolvePcg).
  int min_iterations = 0;
  // Safety net: a solve that reaches it is reported as such.
  int max_iterations = 500;
  // r = b - S y recomputed every this many iterations (one extra product).
  int residual_reset_period = 50;
  PcgPrecision precision = PcgPrecision::kAuto;
  int num_threads = 1;

  // The product's precision that `precision` stands for.
  ProductPrecision product_precision() const {
    if (precision == PcgPrecision::kAuto) {
      return eta > 0.0 ? ProductPrecision::kMixed : ProductPrecision::kDouble;
    }
    return precision == PcgPrecision::kMixed ? ProductPrecision::kMixed : ProductPrecision::kDouble;
  }
};

enum class PcgStop {
  kZeroRhs,
  kQuadraticModel,   // Nash-Sofer test
  kResidual,         // relative residual reached
  kIterationLimit,
  kBreakdown,        // non-positive curvature or not finite
};
const char* PcgStopName(PcgStop stop);

struct PcgSummary {
  int iterations = 0;
  double relative_residual = 0.0;  // ‖r‖ / ‖b‖ at exit (recurrence)
  PcgStop stop = PcgStop::kIterationLimit;
};

// Vectors PCG needs, owned by the caller and reused across solves.
struct PcgScratch {
  std::vector<double> r, z, d, Sd;
  void Resize(int64_t n);
};

// Solves S y = b starting from y = 0. y and b have S.num_rows() entries.
PcgSummary SolvePcg(const SymmetricMultiplier& S, const Preconditioner& M,
                    const double* b, double* y, const PcgOptions& options,
                    PcgScratch* scratch);

}  // namespace dba
