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

void PcgScratch::Resize(int64_t n) {
  r.resize(n);
  z.resize(n);
  d.resize(n);
  Sd.resize(n);
}

PcgSummary SolvePcg(const SymmetricMultiplier& S, const Preconditioner& M,
                    const double* b, double* y, const PcgOptions& options,
                    PcgScratch* scratch) {
  const int64_t n = S.num_rows();
  const int nt = options.num_threads;
  const bool par = n > kParallelBelow;
  scratch->Resize(n);
  double* r = scratch->r.data();
  double* z = scratch->z.data();
  double* d = scratch->d.data();
  double* Sd = scratch->Sd.data();
  PcgSummary summary;
  for (int64_t i = 0; i < n; ++i) {
    y[i] = 0.0;
    r[i] = b[i];
  }
  const double b_norm = std::sqrt(Dot(b, b, n, nt));
  if (b_norm == 0.0) {
    summary.stop = PcgStop::kZeroRhs;
    return summary;
  }
  M.Apply(r, z);
  for (int64_t i = 0; i < n; ++i) d[i] = z[i];
  double rz = Dot(r, z, n, nt);
  double r_norm = b_norm;
  double q_previous = 0.0;  // Q(0)
  summary.stop = PcgStop::kIterationLimit;
  ProgressPhase progress("PCG");
  for (int k = 1; k <= options.max_iterations; ++k) {
    progress.Report(0.0);
    S.Multiply(d, Sd);
    const double dSd = Dot(d, Sd, n, nt);
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
    r_norm = std::sqrt(Dot(r, r, n, nt));
    if (r_norm <= options.relative_tolerance * b_norm) {
      summary.stop = PcgStop::kResidual;
      break;
    }
    if (options.eta > 0.0) {
      // Q(y) = ½ yᵀS y - bᵀy = -½ yᵀ(b + r).
      double yb = 0.0, yr = 0.0;
#pragma omp parallel for num_threads(nt) reduction(+ : yb, yr) schedule(static) if (par)
      for (int64_t i = 0; i < n; ++i) {
        yb += y[i] * b[i];
        yr += y[i] * r[i];
      }
      const double q = -0.5 * (yb + yr);
      if (q < 0.0 && k >= options.min_iterations && k * (q - q_previous) / q < options.eta) {
        summary.stop = PcgStop::kQuadraticModel;
        break;
      }
      q_previous = q;
    }
    M.Apply(r, z);
    const double rz_new = Dot(r, z, n, nt);
    const double beta = rz_new / rz;
    rz = rz_new;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
  }
  summary.relative_residual = r_norm / b_norm;
  return summary;
}

}  // namespace dba
