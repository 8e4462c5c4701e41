// The RCS spread over the ranks (docs/design.md §4.1): no rank holds all of
// it. Each global block row i of S (paper eq. 4) has one owner, the rank
// whose points put the most values into it (so a rank owns the cameras its
// points mostly see); the owner holds row i's stored blocks S_ij (j >= i,
// upper triangle as in BSMC), b_i, g_i and diag(U)_i.
//
//   Reduce     reduce-scatter: every rank sends the blocks and row vectors of
//              its sub-RCS to their rows' owners, one message per pair of
//              ranks that share rows; owners add them in rank order (the
//              same sum on every run).
//   Solve      PCG (solver/pcg.h) on the owners' rows. The product y = S x
//              with upper-triangle storage: each rank fetches the x_j of the
//              columns its rows touch from their owners (the halo), applies
//              its blocks both ways over its rows and the halo, and returns
//              the halo's transposed partial sums to their owners. Dot
//              products: one fused all-reduce per iteration (PCG's
//              predict-and-recompute form, solver/pcg.h). The
//              preconditioner: block-Jacobi on each rank's own rows, plus (two-
//              level, the default) a coarse correction over aggregates of a
//              rank's own rows, the coarse matrix summed and factorized on
//              the main rank, R r gathered there and the coarse solution
//              sent back once per PCG iteration.
//              Terms of residuals on a camera's pose alone (camera-centre
//              priors) come from the main rank to their rows' owners with
//              the reduce-scatter, and are added after the sums.
//              Between a Solve and the next Reduce the own rows' values
//              are freed (the ranks' sub-RCSs too, after Reduce): a rank
//              holds both only while they are summed: through PCG its
//              rows of S and not its sub-RCS.
//   SpreadStep every rank receives δc for the rows its points see from
//              their owners; the main rank all of δc (for the LM decisions).
//
// Local numbering on a rank: its own rows first (in global order), then the
// halo rows (global order). Since every stored block has j >= i globally and
// both groups keep the global order, a local block is upper too; halo rows
// hold only a zero diagonal block (BSMC wants one per row).
//
// Thread safety: collective over the communicator; one caller per rank.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/bsmc/symmetric_multiply.h"
#include "dba/cluster/communicator.h"
#include "dba/rcs/form_rcs.h"
#include "dba/rcs/pose_row_term.h"
#include "dba/solver/coarse_row_basis.h"
#include "dba/solver/preconditioner.h"
#include "dba/solver/rcs_solver.h"

namespace dba {

// What the ranks' sub-systems sum to besides S and b (the same on every rank
// after Reduce).
struct RcsTotals {
  double cost = 0.0;
  ResidualSums residuals;
  double max_abs_gradient = 0.0;  // ‖(g_c, g_p)‖∞
};

class DistributedRcs {
 public:
  // Collective symbolic phase. `global_block_sizes`: every global row's
  // size (the same on every rank); `sub`: this rank's sub-RCS structure, or
  // null for a rank without points; `sub_rows`: the global row of each of
  // its rows. `options`: the linear solve's (PCG, preconditioner,
  // threads). `global_bases` (main rank; empty: identity): the two-level
  // preconditioner's basis of every global row.
  DistributedRcs(Communicator* comm, std::vector<int32_t> global_block_sizes,
                 const BsmcMatrix* sub, std::vector<int32_t> sub_rows,
                 const LinearSolverOptions& options,
                 const std::vector<CoarseRowBasis>& global_bases = {});
  ~DistributedRcs();

  // Collective: the owners' rows from every rank's sub-system (null: a rank
  // without points); the totals are the same on every rank. With
  // `with_pose_terms` (the same on every rank), the main rank's `pose_terms`
  // (rows in global numbering, fixed cameras' left out) go to their rows'
  // owners, who add them after the sub-systems (rcs/pose_row_term.h).
  RcsTotals Reduce(const RcsSystem* sub, bool with_pose_terms = false,
                   const std::vector<PoseRowTerm>& pose_terms = {});

  // Collective: damps the own rows by λ and solves S δc = b by PCG; the
  // result stays here for SpreadStep. The summary is the same on every rank.
  LinearSolveSummary Solve(double lambda, const DampingBounds& bounds);

  // Collective: `sub_delta` (if not null) gets δc of the sub-RCS's rows, in
  // their order; on the main rank `global_delta` (if not null) all of δc in
  // the global layout.
  void SpreadStep(std::vector<double>* sub_delta, std::vector<double>* global_delta);

  // The least λ the solve is reliable at (solver/pcg.h, MinLambda).
  double min_lambda() const { return MinLambda(multiplier_->precision()); }
  // Every rank, between solves: RcsSolver::DropDampingFloor.
  bool DropDampingFloor() { return dba::DropDampingFloor(options_.pcg.precision, multiplier_.get()); }
  int32_t num_own_rows() const { return n_own_; }
  const BsmcMatrix& own_matrix() const { return S_; }
  // The global row of each local row of own_matrix() (own, then halo).
  const std::vector<int32_t>& local_rows() const { return local_rows_; }
  // Bytes this rank holds for its rows (S's structure and values, vectors,
  // preconditioner, product scratch).
  int64_t MemoryBytes() const;

 private:
  class Operator;
  struct Plan;
  void Multiply(const double* x, double* y) const;
  void ExchangeHalo(const std::vector<std::vector<int32_t>>& out_rows,
                    const std::vector<int64_t>& in_scalars, const double* from) const;
  void BuildTwoLevel(const std::vector<CoarseRowBasis>& global_bases);
  std::vector<int32_t> OwnAggregationOrder() const;
  void PlanHaloAndStep(const std::vector<int32_t>& local_of);
  void MakeSolverStorage(const std::vector<CoarseRowBasis>& global_bases);
  void AddPoseTerms(const std::vector<PoseRowTerm>& pose_terms);

  Communicator* comm_;
  std::vector<int32_t> global_sizes_;
  std::vector<int64_t> global_offset_;  // scalar offset of each global row
  std::vector<int32_t> owner_;          // global row -> rank
  // The global rows in the order of the cameras' places (the main rank's
  // options.aggregation_order, on every rank; empty: row order): the owners'
  // balanced ranges and the aggregates follow it.
  std::vector<int32_t> order_;
  int32_t n_own_ = 0;
  std::vector<int32_t> local_rows_;     // own rows then halo rows (global ids)
  const BsmcMatrix* sub_ = nullptr;
  std::vector<int32_t> sub_rows_;
  BsmcMatrix S_;                        // own rows, then the halo's
  std::vector<double> b_, gradient_, jtj_diagonal_;  // own rows
  std::unique_ptr<Plan> plan_;
  LinearSolverOptions options_;
  std::unique_ptr<SymmetricMultiplier> multiplier_;
  std::unique_ptr<Preconditioner> preconditioner_;
  std::unique_ptr<Operator> operator_;
  PcgScratch scratch_;
  std::vector<double> delta_;             // own rows' δc
  mutable std::vector<double> x_ext_, y_ext_;  // product scratch, own + halo
};

}  // namespace dba
