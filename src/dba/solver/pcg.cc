// PCG with a truncated-Newton stop (paper eq. 6-7; Nash & Sofer 1990); see pcg.h.
#include "dba/solver/pcg.h"

#include <cmath>

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
  const int64_t n = S.num_rows();
  const int nt = options.num_threads;
  const bool par = n > kParallelBelow;
  scratch->Resize(n);
  double* r = scratch->vectors.data();
  double* z = r + n;
  double* d = z + n;
  double* Sd = d + n;
  PcgSummary summary;
  for (int64_t i = 0; i < n; ++i) {
    y[i] = 0.0;
    r[i] = b[i];
  }
  M.Apply(r, z);
  for (int64_t i = 0; i < n; ++i) d[i] = z[i];
  double start[2] = {Dot(b, b, n, nt), Dot(r, z, n, nt)};
  S.SumOverRanks(start);
  const double b_norm = std::sqrt(start[0]);
  double rz = start[1];
  if (b_norm == 0.0) {
    summary.stop = PcgStop::kZeroRhs;
    return summary;
  }
  double r_norm = b_norm;
  double q_previous = 0.0;  // Q(0)
  summary.stop = PcgStop::kIterationLimit;
  ProgressPhase progress("PCG");
  for (int k = 1; k <= options.max_iterations; ++k) {
    progress.Report(0.0);
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
    // The next direction's z before the tests, so that every sum of the
    // iteration goes in one reduction.
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
    r_norm = std::sqrt(sums[0]);
    if (r_norm <= options.relative_tolerance * b_norm) {
      summary.stop = PcgStop::kResidual;
      break;
    }
    if (options.eta > 0.0) {
      // Q(y) = ½ yᵀS y - bᵀy = -½ yᵀ(b + r).
      const double q = -0.5 * (sums[1] + sums[2]);
      if (q < 0.0 && k >= options.min_iterations && k * (q - q_previous) / q < options.eta) {
        summary.stop = PcgStop::kQuadraticModel;
        break;
      }
      q_previous = q;
    }
    const double beta = sums[3] / rz;
    rz = sums[3];
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
  }
  summary.relative_residual = r_norm / b_norm;
  return summary;
}

}  // namespace dba
