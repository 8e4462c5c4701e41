// Preconditioned conjugate gradients for S y = b (paper eq. 6-7), S symmetric
// positive definite in BSMC, with a preconditioner M ≈ S:
//
//   r0 = b - S y0, z0 = M⁻¹ r0, d0 = z0
//   α_k = r_kᵀ z_k / d_kᵀ S d_k,  y += α d,  r -= α S d
//   z = M⁻¹ r,  β = r_{k+1}ᵀ z_{k+1} / r_kᵀ z_k,  d = z + β d
//
// In one process, in this (Hestenes and Stiefel's) form. Where the sums go
// over ranks (cluster/distributed_rcs.h), in the predict-and-recompute form
// of Meurant ("Multitasking the conjugate gradient method on the CRAY
// X-MP/48", Parallel Computing 5, 1987), as Chen and Carson analyse it
// ("Predict-and-recompute conjugate gradient variants", SIAM J. Sci.
// Comput. 42(5), 2020): z follows its own recurrence z -= α M⁻¹S d (M is
// applied to S d instead of r), and
//
//   r_{k+1}ᵀ z_{k+1} = α_k² (S d_k)ᵀ M⁻¹ S d_k - r_kᵀ z_k
//
// predicts β with no sum of its own, so every sum of an iteration (dᵀSd,
// (Sd)ᵀM⁻¹Sd, rᵀz recomputed for α, and the stopping tests' rᵀr, yᵀb, yᵀr)
// goes in one all-reduce after the direction's product, against two in the
// textbook form. Unlike Chronopoulos and Gear's one-reduction form (tried
// and not kept: bench/README.md), S d is a product, not a recurrence. The
// same products and preconditioner applications per iteration, one vector
// more, and one product and application more per solve (the last
// direction's, made before the tests that end it). One process keeps the
// textbook form: it has no latency to save, and on the 120° fisheye
// problem of tests/cli_generate.sh, whose tight solves stop at the
// iteration cap, the textbook form's capped steps ended LM within 1e-11 of
// the dense solve's cost, the one-reduction form's 1e-9 to 4e-9 above it in
// three runs of four (other reset periods and tolerances).
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
// solves), and the iteration cap only as a safety net. The recurrences drift
// from r = b - S y (and z = M⁻¹ r) in floating point: they are recomputed
// every `residual_reset_period` iterations.
//
// Thread safety: one solve at a time per scratch and multiplier.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/common/placed_doubles.h"
#include "dba/solver/preconditioner.h"

namespace dba {

// The precision of S in PCG's product (bsmc/symmetric_multiply.h): auto is
// mixed (off-diagonal blocks in float, half the bytes of the product) while
// the η stop is on, which never sees float's rounding of S (6e-8 relative
// per value, far inside η), until LM's damping reaches the floor that
// rounding sets (MinLambda) and would go lower: double from then on
// (RcsSolver::DropDampingFloor). Double for a tight solve (η = 0).
enum class PcgPrecision { kAuto, kMixed, kDouble };
const char* PcgPrecisionName(PcgPrecision precision);
// "auto", "mixed", "double"; false if `name` is none of them.
bool ParsePcgPrecision(const std::string& name, PcgPrecision* precision);

// The least LM damping a mixed-precision product stands: float's unit
// roundoff, 2⁻²⁴ ≈ 6e-8. S's off-diagonal values are rounded by up to that
// much relative; S_λ's smallest eigenvalues, relative to its diagonal, are
// about λ on the weak modes (a nadir survey's f against flying height, per
// image). With λ below the rounding, the narrowed S_λ need not be positive
// definite: measured on the 1M-image survey, PCG broke down at λ = 1.0e-8,
// 9.8e-9, 6.7e-9 and 6.5e-9 with steps 10³ to 10¹⁴ times the cost, four
// wasted LM iterations (bench/README.md, "LM tail").
constexpr double kMixedPrecisionMinLambda = 0x1p-24;
inline double MinLambda(ProductPrecision precision) {
  return precision == ProductPrecision::kMixed ? kMixedPrecisionMinLambda : 0.0;
}
// RcsSolver::DropDampingFloor for a product `requested` as this precision:
// only kAuto's mixed product turns to double (when LM's damping reaches the
// floor and its steps would lower it further). True if it did.
// Measured on the 1M-image survey (bench/README.md, "The damping floor
// dropped"): with the floor λ sat on it from LM iteration 11 with gain
// ratios of 0.93-0.99, and the solve stopped at the function tolerance
// 1.6e-5 above the cost a double product reaches (41 LM iterations against
// 33); tighter PCG solves at the floor (η 0.01) did not lower the cost.
inline bool DropDampingFloor(PcgPrecision requested, SymmetricMultiplier* multiplier) {
  if (requested != PcgPrecision::kAuto || multiplier->precision() != ProductPrecision::kMixed) {
    return false;
  }
  multiplier->UseDoublePrecision();
  return true;
}

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

// Vectors PCG needs (r, z, d, S d: kPcgVectors n doubles; the one-reduction
// form also M⁻¹S d), owned by the caller and reused across solves, or placed
// where the caller lends them for a solve.
constexpr int kPcgVectors = 4;
constexpr int kOneReductionPcgVectors = 5;
struct PcgScratch {
  PlacedDoubles vectors;
  void Resize(int64_t n, int count = kPcgVectors) { vectors.Resize(count * n); }
  // Their pages back to the system between solves (each solve rewrites them).
  void ReturnPages() { vectors.ReturnPages(); }
};

// What PCG needs of S: y = S x over this rank's entries, and the sums of
// partial dot products over the ranks that hold the other entries.
class PcgOperator {
 public:
  virtual ~PcgOperator() = default;
  virtual int64_t num_rows() const = 0;  // entries on this rank
  virtual void Multiply(const double* x, double* y) const = 0;
  // In place: each partial sum summed over the ranks (one reduction).
  virtual void SumOverRanks(std::span<double> partial) const { (void)partial; }
  // True where SumOverRanks communicates: SolvePcg then makes one reduction
  // per iteration (the predict-and-recompute form).
  virtual bool SumsOverRanks() const { return false; }
};

// S in one process.
class LocalPcgOperator : public PcgOperator {
 public:
  explicit LocalPcgOperator(const SymmetricMultiplier& S) : S_(S) {}
  int64_t num_rows() const override { return S_.num_rows(); }
  void Multiply(const double* x, double* y) const override { S_.Multiply(x, y); }

 private:
  const SymmetricMultiplier& S_;
};

// Solves S y = b starting from y = 0. y and b have S.num_rows() entries.
PcgSummary SolvePcg(const PcgOperator& S, const Preconditioner& M, const double* b, double* y,
                    const PcgOptions& options, PcgScratch* scratch);
inline PcgSummary SolvePcg(const SymmetricMultiplier& S, const Preconditioner& M,
                           const double* b, double* y, const PcgOptions& options,
                           PcgScratch* scratch) {
  return SolvePcg(LocalPcgOperator(S), M, b, y, options, scratch);
}

}  // namespace dba
