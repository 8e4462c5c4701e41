// PCG with a truncated-Newton stop (paper eq. 6-7; Nash & Sofer 1990), in the
// textbook form and the one-reduction form; see pcg.h.
#include "dba/solver/pcg.h"

#include <cmath>
#include <optional>

#include "dba/common/interrupt.h"
#include "dba/common/progress.h"

namespace dba {
namespace {

constexpr int64_t kParallelBelow = 8192;  // shorter vectors: serial loops

double Dot(const double* a, const double* b, int64_t n, int num_threads) {
  double s = 0.0;
#pragma omp parallel for num_threads(num_threads) reduction(+ : s) schedule(static) if (n > kParallelBelow)
  for (int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

// y0 = 0, r0 = b, z0 = M⁻¹ r0, d0 = z0.
void StartAtZero(const Preconditioner& M, const double* b, int64_t n, double* y, double* r,
                 double* z, double* d) {
  for (int64_t i = 0; i < n; ++i) {
    y[i] = 0.0;
    r[i] = b[i];
  }
  M.Apply(r, z);
  for (int64_t i = 0; i < n; ++i) d[i] = z[i];
}

// The stopping tests after iteration k, from rᵀr, yᵀb and yᵀr of its iterate.
class StopTests {
 public:
  StopTests(const PcgOptions& options, double b_norm) : options_(options), b_norm_(b_norm) {}
  std::optional<PcgStop> After(int k, double rr, double yb, double yr) {
    r_norm_ = std::sqrt(rr);
    if (r_norm_ <= options_.relative_tolerance * b_norm_) return PcgStop::kResidual;
    if (options_.eta > 0.0) {
      // Q(y) = ½ yᵀS y - bᵀy = -½ yᵀ(b + r).
      const double q = -0.5 * (yb + yr);
      if (q < 0.0 && k >= options_.min_iterations && k * (q - q_previous_) / q < options_.eta) {
        return PcgStop::kQuadraticModel;
      }
      q_previous_ = q;
    }
    return std::nullopt;
  }
  double relative_residual() const { return r_norm_ / b_norm_; }

 private:
  const PcgOptions& options_;
  const double b_norm_;
  double r_norm_ = b_norm_;
  double q_previous_ = 0.0;  // Q(0)
};

// Hestenes and Stiefel's form: two reductions per iteration (dᵀSd; then rᵀr,
// yᵀb, yᵀr, rᵀz together, M applied before the tests for that).
PcgSummary SolveTextbook(const PcgOperator& S, const Preconditioner& M, const double* b, double* y,
                         const PcgOptions& options, PcgScratch* scratch) {
  const int64_t n = S.num_rows();
  const int nt = options.num_threads;
  const bool par = n > kParallelBelow;
  scratch->Resize(n);
  double* r = scratch->vectors.data();
  double* z = r + n;
  double* d = z + n;
  double* Sd = d + n;
  PcgSummary summary;
  StartAtZero(M, b, n, y, r, z, d);
  double start[2] = {Dot(b, b, n, nt), Dot(r, z, n, nt)};
  S.SumOverRanks(start);
  const double b_norm = std::sqrt(start[0]);
  double rz = start[1];
  if (b_norm == 0.0) {
    summary.stop = PcgStop::kZeroRhs;
    return summary;
  }
  StopTests tests(options, b_norm);
  summary.stop = PcgStop::kIterationLimit;
  ProgressPhase progress("PCG");
  for (int k = 1; k <= options.max_iterations; ++k) {
    progress.Report(0.0);
    PollInterrupt();
    S.Multiply(d, Sd);
    double dSd = Dot(d, Sd, n, nt);
    S.SumOverRanks(std::span<double>(&dSd, 1));
    if (!(dSd > 0.0) || !std::isfinite(dSd)) {
      summary.stop = PcgStop::kBreakdown;
      break;
    }
    const double alpha = rz / dSd;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) {
      y[i] += alpha * d[i];
      r[i] -= alpha * Sd[i];
    }
    if (options.residual_reset_period > 0 && k % options.residual_reset_period == 0) {
      S.Multiply(y, Sd);  // r = b - S y, the recurrence's drift removed
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
      for (int64_t i = 0; i < n; ++i) r[i] = b[i] - Sd[i];
    }
    summary.iterations = k;
    M.Apply(r, z);
    double rr = 0.0, yb = 0.0, yr = 0.0, rz_new = 0.0;
#pragma omp parallel for num_threads(nt) reduction(+ : rr, yb, yr, rz_new) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) {
      rr += r[i] * r[i];
      yb += y[i] * b[i];
      yr += y[i] * r[i];
      rz_new += r[i] * z[i];
    }
    double sums[4] = {rr, yb, yr, rz_new};
    S.SumOverRanks(sums);
    if (const auto stop = tests.After(k, sums[0], sums[1], sums[2])) {
      summary.stop = *stop;
      break;
    }
    const double beta = sums[3] / rz;
    rz = sums[3];
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
  }
  summary.relative_residual = tests.relative_residual();
  return summary;
}

// Meurant's predict-and-recompute form: one reduction per iteration.
PcgSummary SolveOneReduction(const PcgOperator& S, const Preconditioner& M, const double* b,
                             double* y, const PcgOptions& options, PcgScratch* scratch) {
  const int64_t n = S.num_rows();
  const int nt = options.num_threads;
  const bool par = n > kParallelBelow;
  scratch->Resize(n, kOneReductionPcgVectors);
  double* r = scratch->vectors.data();
  double* z = r + n;  // M⁻¹ r, by its own recurrence
  double* d = z + n;
  double* Sd = d + n;
  double* MSd = Sd + n;  // M⁻¹ S d
  PcgSummary summary;
  StartAtZero(M, b, n, y, r, z, d);
  // Every sum of an iteration, in the one reduction that follows the
  // direction's product: dᵀSd, (Sd)ᵀM⁻¹Sd, rᵀz (recomputed), and for the
  // stopping tests rᵀr, yᵀb, yᵀr (of the iterate before the product).
  enum { kDSd, kSdMSd, kRz, kRr, kYb, kYr, kSums };
  double sums[kSums];
  auto direction_and_sums = [&]() {
    S.Multiply(d, Sd);
    M.Apply(Sd, MSd);
    double dSd = 0.0, SdMSd = 0.0, rz = 0.0, rr = 0.0, yb = 0.0, yr = 0.0;
#pragma omp parallel for num_threads(nt) reduction(+ : dSd, SdMSd, rz, rr, yb, yr) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) {
      dSd += d[i] * Sd[i];
      SdMSd += Sd[i] * MSd[i];
      rz += r[i] * z[i];
      rr += r[i] * r[i];
      yb += y[i] * b[i];
      yr += y[i] * r[i];
    }
    sums[kDSd] = dSd;
    sums[kSdMSd] = SdMSd;
    sums[kRz] = rz;
    sums[kRr] = rr;
    sums[kYb] = yb;
    sums[kYr] = yr;
    S.SumOverRanks(sums);
  };
  direction_and_sums();
  const double b_norm = std::sqrt(sums[kRr]);  // r = b, y = 0
  if (b_norm == 0.0) {
    summary.stop = PcgStop::kZeroRhs;
    return summary;
  }
  StopTests tests(options, b_norm);
  summary.stop = PcgStop::kIterationLimit;
  ProgressPhase progress("PCG");
  for (int k = 1; k <= options.max_iterations; ++k) {
    progress.Report(0.0);
    PollInterrupt();
    const double dSd = sums[kDSd], rz = sums[kRz];
    if (!(dSd > 0.0) || !std::isfinite(dSd) || !std::isfinite(sums[kSdMSd])) {
      summary.stop = PcgStop::kBreakdown;
      break;
    }
    const double alpha = rz / dSd;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) {
      y[i] += alpha * d[i];
      r[i] -= alpha * Sd[i];
      z[i] -= alpha * MSd[i];
    }
    summary.iterations = k;
    // r_kᵀz_k predicted as α² (Sd)ᵀM⁻¹Sd - r_{k-1}ᵀz_{k-1} gives β without a
    // sum of its own; the next reduction recomputes it for α. A prediction
    // that rounding left non-positive restarts the directions (β = 0).
    double rz_next = alpha * alpha * sums[kSdMSd] - rz;
    if (options.residual_reset_period > 0 && k % options.residual_reset_period == 0) {
      S.Multiply(y, Sd);  // r = b - S y and z = M⁻¹ r: the recurrences' drift removed
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
      for (int64_t i = 0; i < n; ++i) r[i] = b[i] - Sd[i];
      M.Apply(r, z);
      rz_next = Dot(r, z, n, nt);  // β from the new r and z: a reduction once per period
      S.SumOverRanks(std::span<double>(&rz_next, 1));
    }
    const double beta = rz_next > 0.0 ? rz_next / rz : 0.0;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
    // The next direction's product before the tests, so that its sums and
    // the tests' share the iteration's one reduction; the last one is
    // computed for nothing.
    direction_and_sums();
    if (const auto stop = tests.After(k, sums[kRr], sums[kYb], sums[kYr])) {
      summary.stop = *stop;
      break;
    }
  }
  summary.relative_residual = tests.relative_residual();
  return summary;
}

}  // namespace

const char* PcgStopName(PcgStop stop) {
  switch (stop) {
    case PcgStop::kZeroRhs: return "zero_rhs";
    case PcgStop::kQuadraticModel: return "quadratic_model";
    case PcgStop::kResidual: return "residual";
    case PcgStop::kIterationLimit: return "iteration_limit";
    case PcgStop::kBreakdown: return "breakdown";
  }
  return "unknown";
}

const char* PcgPrecisionName(PcgPrecision precision) {
  switch (precision) {
    case PcgPrecision::kAuto: return "auto";
    case PcgPrecision::kMixed: return "mixed";
    case PcgPrecision::kDouble: return "double";
  }
  return "unknown";
}

bool ParsePcgPrecision(const std::string& name, PcgPrecision* precision) {
  for (PcgPrecision p : {PcgPrecision::kAuto, PcgPrecision::kMixed, PcgPrecision::kDouble}) {
    if (name == PcgPrecisionName(p)) {
      *precision = p;
      return true;
    }
  }
  return false;
}

PcgSummary SolvePcg(const PcgOperator& S, const Preconditioner& M, const double* b, double* y,
                    const PcgOptions& options, PcgScratch* scratch) {
  return S.SumsOverRanks() ? SolveOneReduction(S, M, b, y, options, scratch)
                           : SolveTextbook(S, M, b, y, options, scratch);
}

}  // namespace dba
