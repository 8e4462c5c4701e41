// Formation of the reduced camera system point by point (paper eq. 4,
// section 5): S = Σ_k (sub-RCS of point k), b = Σ_k (rhs of point k).
//
// S holds U - W V_λ⁻¹ Wᵀ with U undamped: the camera damping λ D_c needs
// diag(U) summed over all points (over all ranks in a distributed run), so it
// is added afterwards (DampCameraBlocks), from `camera_side_jtj_diagonal`.
//
// Rows are the unknowns of rcs/unknown_layout.h: cameras (or poses) first,
// then intrinsic groups.
//
// Threads: points are processed in parallel. While one copy of the RCS per
// thread fits in 32 MiB, each thread adds into its own copy and the copies
// are summed in thread order (no locks; small RCSs, where all points touch
// the same rows). Otherwise a point's blocks in block row i are added under
// the lock of row i (striped spinlocks), one row at a time.
//
// Thread safety: FormRcs uses its own threads; do not call it concurrently on
// the same RcsSystem.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/problem/problem.h"
#include "dba/rcs/eliminate_point.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

// The linear system of one rank's points, cameras in that rank's numbering.
struct RcsSystem {
  UnknownLayout layout;                     // rows of S: which parameters move
  BsmcMatrix S;                             // U - W V_λ⁻¹ Wᵀ, U undamped
  std::vector<double> b;                    // -g_c + W V_λ⁻¹ g_p
  std::vector<double> camera_side_gradient;      // g_c = J_cᵀ r
  std::vector<double> camera_side_jtj_diagonal;  // diag(U) = diag(J_cᵀ J_c)
  double cost = 0.0;                        // ½ Σ ρ(|r|²)
  ResidualSums residuals;                   // plain |r|², all and inliers
  double max_abs_point_gradient = 0.0;      // ‖g_p‖∞
  // FormRcs's: per row of S, whether points of more than one thread's range
  // touch it (those rows are locked), for `shared_rows_threads` threads and
  // a problem of `shared_rows_observations` observations.
  std::vector<uint8_t> shared_rows;
  int shared_rows_threads = 0;
  int64_t shared_rows_observations = -1;

  // Symbolic phase: unknowns and structure of S from the problem's
  // visibility graph. `before_values`, if set, sees the system with S's
  // structure but before any value is allocated (the pattern freed): to size
  // the solve, or refuse it by throwing. `with_values` false: the structure
  // alone (AllocateValues to finish).
  // `lever_arm`: the layout has the camera priors' lever arm's row.
  static RcsSystem ForProblem(const Problem& problem,
                              const std::function<void(const RcsSystem&)>& before_values = {},
                              bool with_values = true, bool lever_arm = false);
  // Symbolic phase from a block pattern over the layout's rows (sorted packed
  // blocks, see PackBlock); `with_values` false: the structure alone
  // (AllocateValues to finish).
  static RcsSystem ForPattern(UnknownLayout layout, std::span<const uint64_t> pattern,
                              bool with_values = true);
  // S's values and the vectors b, gradient and diagonal, zeroed.
  void AllocateValues();
};

// Numeric phase: refills `system` at the problem's current parameters, for
// the robust cost ½ Σ ρ(|r|²) of `loss` (default: the squared loss).
void FormRcs(const Problem& problem, double lambda,
             const DampingBounds& bounds, int num_threads, RcsSystem* system,
             const RobustLoss& loss = RobustLoss());

// Bytes of the threads' private copies of the RCS (S's `values`, and b,
// gradient and diagonal over `rows`) that FormRcs allocates on each call
// when they are small enough to beat row locks (32 MiB in all), else 0.
int64_t FormationCopyBytes(int64_t values, int64_t rows, int num_threads);

// S_ii += λ clamp(diag U_ii) on every diagonal block (the camera part of the
// Marquardt damping λ D); `num_block_rows` >= 0: on the first rows only (a
// rank's own rows of a distributed RCS).
void DampCameraBlocks(double lambda, const DampingBounds& bounds,
                      const std::vector<double>& camera_side_jtj_diagonal,
                      BsmcMatrix* S, int32_t num_block_rows = -1);

}  // namespace dba
