// PCG with block-Jacobi preconditioning (paper eq. 6-7); see pcg.h.
#include "dba/solver/pcg.h"

#include <cmath>
#include <vector>

namespace dba {
namespace {

double Dot(const std::vector<double>& a, const std::vector<double>& b,
           int num_threads) {
  double s = 0.0;
  const int64_t n = static_cast<int64_t>(a.size());
#pragma omp parallel for num_threads(num_threads) reduction(+ : s) schedule(static) if (n > 8192)
  for (int64_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

PcgSummary SolvePcg(const SymmetricMultiplier& S,
                    const BlockJacobiPreconditioner& M, const double* b,
                    double* y, const PcgOptions& options) {
  const int64_t n = S.num_rows();
  const int nt = options.num_threads;
  const bool par = n > 8192;
  PcgSummary summary;
  std::vector<double> r(b, b + n), z(n), d(n), Sd(n);
  for (int64_t i = 0; i < n; ++i) y[i] = 0.0;
  const double b_norm = std::sqrt(Dot(r, r, nt));
  if (b_norm == 0.0) {
    summary.converged = true;
    summary.message = "zero right-hand side";
    return summary;
  }
  M.Apply(r.data(), z.data());
  d = z;
  double rz = Dot(r, z, nt);
  double r_norm = b_norm;
  for (int k = 0; k < options.max_iterations; ++k) {
    if (r_norm <= options.relative_tolerance * b_norm) break;
    S.Multiply(d.data(), Sd.data());
    const double dSd = Dot(d, Sd, nt);
    if (!(dSd > 0.0) || !std::isfinite(dSd)) {
      summary.message = "breakdown: direction of non-positive curvature";
      break;
    }
    const double alpha = rz / dSd;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) {
      y[i] += alpha * d[i];
      r[i] -= alpha * Sd[i];
    }
    M.Apply(r.data(), z.data());
    const double rz_new = Dot(r, z, nt);
    const double beta = rz_new / rz;
    rz = rz_new;
#pragma omp parallel for num_threads(nt) schedule(static) if (par)
    for (int64_t i = 0; i < n; ++i) d[i] = z[i] + beta * d[i];
    r_norm = std::sqrt(Dot(r, r, nt));
    summary.iterations = k + 1;
  }
  summary.relative_residual = r_norm / b_norm;
  summary.converged = summary.relative_residual <= options.relative_tolerance;
  if (summary.message.empty()) {
    summary.message = summary.converged ? "relative residual reached"
                                        : "iteration limit reached";
  }
  return summary;
}

}  // namespace dba
