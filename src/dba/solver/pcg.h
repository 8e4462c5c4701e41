// Preconditioned conjugate gradients for S y = b (paper eq. 6-7), S symmetric
// positive definite in BSMC, with a block-Jacobi preconditioner:
//
//   r0 = b - S y0, z0 = M⁻¹ r0, d0 = z0
//   α_k = r_kᵀ z_k / d_kᵀ S d_k,  y += α d,  r -= α S d
//   z = M⁻¹ r,  β = r_{k+1}ᵀ z_{k+1} / r_kᵀ z_k,  d = z + β d
// until ‖r_k‖ ≤ relative_tolerance ‖b‖ or max_iterations.
//
// Thread safety: runs its own threads; one solve at a time per multiplier.
#pragma once

#include <string>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/solver/block_jacobi.h"

namespace dba {

struct PcgOptions {
  // Stop when ‖b - S y‖ ≤ relative_tolerance · ‖b‖. Tight by default: with
  // 1e-2 or 1e-1 LM still reaches the exact optimum on the shared BAL
  // problems with fewer PCG iterations, but where it stops then depends on
  // rounding, so runs with different thread or rank counts end up to 1e-6
  // apart instead of 1e-11.
  double relative_tolerance = 1e-6;
  // Hard cap on iterations.
  int max_iterations = 500;
  int num_threads = 1;
};

struct PcgSummary {
  int iterations = 0;
  double relative_residual = 0.0;  // ‖b - S y‖ / ‖b‖ at exit
  bool converged = false;          // false: iteration cap, or breakdown
  std::string message;
};

// Solves S y = b starting from y = 0. y and b have S.num_rows() entries.
PcgSummary SolvePcg(const SymmetricMultiplier& S,
                    const BlockJacobiPreconditioner& M, const double* b,
                    double* y, const PcgOptions& options);

}  // namespace dba
