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
// Threads: points are processed in parallel, each thread a contiguous
// range. While one copy of the RCS per thread fits in 32 MiB, each thread
// adds into its own copy and the copies are summed in thread order (no
// locks; small RCSs, where all points touch the same rows). Otherwise each
// thread adds the rows only its points touch into S itself, and the rows
// several threads' points touch (the seams between ranges) the first thread
// into S and each later one into its own sums of them, added in thread
// order afterwards: the same bits on every run, while what those sums hold
// (each later thread's pages only the rows its points touch, about those
// at its range's two ends) is at most an eighth of the RCS
// (FormationSeamBytesLimit). Past that (an input whose order scatters
// every row over the threads), a point's blocks in a shared row i are added
// under the lock of row i (striped spinlocks), in the order the threads
// come.
//
// Thread safety: FormRcs uses its own threads; do not call it concurrently on
// the same RcsSystem.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
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
  // The doubles of the shared rows each later thread's points touch,
  // summed over those threads (what their own sums of them hold).
  int64_t shared_rows_later_doubles = 0;
  // FormRcs's last: the doubles of each later thread's sums of the shared
  // rows, as laid out (0: private copies, one thread, or row locks).
  int64_t seam_doubles = 0;
  // Those sums, kept zero between formations (made with the shared rows;
  // a copy of the system shares them: form one copy at a time).
  std::shared_ptr<struct FormationSeams> seams;

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
// Without private copies: the most the later threads' sums of the rows
// they share take (an eighth of the RCS); 0 with one thread or private
// copies. Seam rows beyond it are summed under locks instead.
int64_t FormationSeamBytesLimit(int64_t values, int64_t rows, int num_threads);

// S_ii += λ clamp(diag U_ii) on every diagonal block (the camera part of the
// Marquardt damping λ D); `num_block_rows` >= 0: on the first rows only (a
// rank's own rows of a distributed RCS).
void DampCameraBlocks(double lambda, const DampingBounds& bounds,
                      const std::vector<double>& camera_side_jtj_diagonal,
                      BsmcMatrix* S, int32_t num_block_rows = -1);

}  // namespace dba
