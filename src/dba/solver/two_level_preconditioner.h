// Two-level additive preconditioner for the RCS (Konolige & Brown,
// "Multigrid for bundle adjustment", arXiv 2007.01941; the additive form of
// two-level Schwarz methods):
//
//   M⁻¹ = B⁻¹ + Rᵀ (R S Rᵀ)⁻¹ R
//
// B is block-Jacobi (blockdiag S_ii). R aggregates neighbouring camera
// blocks: block rows of equal size and basis kind that share points are
// grouped greedily (about `aggregate_size` each). Each row i has a basis N_i
// of its unknowns (CoarseRowBasis) and R's block for it is N_iᵀ, so Rᵀ moves
// all rows of an aggregate by the same coarse coordinates: with the identity
// basis the same parameter step, with the rigid-motion basis of
// rcs/rigid_motion_basis.h the same motion of the scene (a translation and a
// rotation shared by cameras of different headings). The coarse matrix
// R S Rᵀ = Σ N_iᵀ S_ij N_j (9x9 blocks per aggregate pair for BAL cameras) is
// summed from S's blocks and factorized once per linear solve by the dense or
// sparse Cholesky; block-Jacobi damps the short-wavelength error, the coarse
// solve the long-wavelength bending of long flight strips that block-Jacobi
// leaves to hundreds of PCG iterations. The rigid-motion basis takes a
// quarter fewer PCG iterations than the identity on the 10,000-image
// surveys of bench/README.md.
//
// Distributed (the RCS spread over ranks, cluster/distributed_rcs.h): each
// rank aggregates its own rows (aggregates do not cross ranks) and sums its
// rows' part of R S Rᵀ in the global aggregate numbering; the coarse solver
// it is given sums the ranks' parts and solves on one rank. B⁻¹ is
// rank-local.
//
// Thread safety: Apply is const but uses scratch: one Apply at a time.
#pragma once

#include <memory>
#include <vector>

#include "dba/common/placed_doubles.h"
#include "dba/solver/block_jacobi.h"
#include "dba/solver/coarse_row_basis.h"
#include "dba/solver/preconditioner.h"
#include "dba/solver/rcs_solver.h"

namespace dba {

// Aggregates of S's block rows: aggregate[i] for each block row, grouping
// rows of equal size (and equal `kind[i]`, when given) connected in S's
// block graph, about `target` rows each.
// `num_block_rows` >= 0: the first rows only, joined by the blocks among
// them (a rank's own rows). `order` (empty: row order): the rows in the
// order the aggregation meets them, as seeds and as neighbours; the
// aggregates are then the same sets under any numbering of the rows that
// keeps that order.
std::vector<int32_t> AggregateBlockRows(const BsmcMatrix& S, int target,
                                        const std::vector<uint8_t>& kind = {},
                                        int32_t num_block_rows = -1,
                                        const std::vector<int32_t>& order = {});

// The two-level space's per-row bases as the preconditioner uses them:
// checked against S (one per row of `kind`), and the scale columns settled
// (see the .cc) over `aggregate` (one per row). Throws std::invalid_argument
// on a basis that does not fit its row.
std::vector<uint8_t> BasisKinds(const BsmcMatrix& S, const std::vector<CoarseRowBasis>& bases);
// `scaled_elsewhere`: scaled aggregates of other ranks (they count toward
// the two a coarse space with scale needs).
void SettleScaleColumns(const std::vector<int32_t>& aggregate, int32_t num_aggregates,
                        std::vector<CoarseRowBasis>* bases, int64_t scaled_elsewhere = 0);
// Aggregates of more than one row with a scale column among them.
int64_t ScaledAggregates(const std::vector<int32_t>& aggregate, int32_t num_aggregates,
                         const std::vector<CoarseRowBasis>& bases);

class TwoLevelPreconditioner : public Preconditioner {
 public:
  // Symbolic: aggregates, coarse pattern, map from S's blocks to coarse
  // blocks, the coarse solver's analysis. S must outlive this object.
  // `bases`: one per block row of S; empty: identity for all.
  TwoLevelPreconditioner(const BsmcMatrix& S, int aggregate_size, int num_threads,
                         std::vector<CoarseRowBasis> bases = {},
                         const std::vector<int32_t>& aggregation_order = {});
  // A rank's part: S's first `num_own_rows` rows are preconditioned (the
  // rest is halo); `aggregate` gives every row of S its aggregate in the
  // global numbering, `coarse_sizes` every aggregate's coarse size, `bases`
  // every row's basis, settled (empty: identity). `coarse_solver` factorizes
  // and solves the coarse matrix from this rank's part of it (the sum over
  // the ranks is its business); its SolveFactored gets and returns the
  // whole coarse vector, of which this rank's aggregates are read.
  TwoLevelPreconditioner(const BsmcMatrix& S, int num_threads, int32_t num_own_rows,
                         std::vector<int32_t> aggregate, std::vector<int32_t> coarse_sizes,
                         std::vector<CoarseRowBasis> bases,
                         std::unique_ptr<CholeskySolver> coarse_solver);
  void Update(const BsmcMatrix& S) override;
  void Apply(const double* r, double* z) const override;
  int64_t MemoryBytes() const override;
  void ReturnNumericPages() override;
  // Block-Jacobi's inverses and the coarse matrix's values (the coarse
  // factor is the coarse solver's own; the threads' partial sums of the
  // coarse matrix are too, given back as soon as summed: their number
  // grows with the threads, and the place lent must not).
  int64_t NumericDoubles() const override;
  void PlaceNumeric(double* place) override;

  int32_t num_aggregates() const { return coarse_.num_block_rows(); }
  // The coarse matrix R S Rᵀ as last updated (for tests; its values only
  // while the place lent for them is not the lender's again).
  const BsmcMatrix& coarse() const { return coarse_; }
  const std::vector<int32_t>& aggregate() const { return aggregate_; }
  // The bases in use: those given, less the scale of rows alone in their
  // aggregate (for tests).
  const std::vector<CoarseRowBasis>& bases() const { return bases_; }

 private:
  // Row i's basis (the identity where none was given).
  const CoarseRowBasis& Basis(int32_t i) const {
    static const CoarseRowBasis identity;
    return bases_.empty() ? identity : bases_[i];
  }
  // Coarse coordinates of block row i: its unknowns, one more with a scale
  // column.
  int CoarseSize(int32_t i) const {
    return S_.block_size(i) + (!bases_.empty() && bases_[i].scale ? 1 : 0);
  }
  // The coarse pattern, its map from S's blocks, the threads' row split.
  void BuildCoarse(std::vector<int32_t> coarse_sizes, int num_threads);
  // coarse_'s values: R S Rᵀ from S's.
  void SumCoarse(const BsmcMatrix& S);

  const BsmcMatrix& S_;
  int32_t n_;  // rows preconditioned (a rank's own)
  BlockJacobiPreconditioner jacobi_;
  std::vector<int32_t> aggregate_;      // block row -> aggregate
  BsmcMatrix coarse_;
  std::vector<int64_t> coarse_block_;   // S block -> coarse block
  std::vector<uint8_t> transposed_;     // S block lands transposed
  std::vector<uint8_t> mirrored_;       // S block i < j in one aggregate: also add Sᵀ
  std::vector<CoarseRowBasis> bases_;   // empty: identity
  std::vector<int32_t> thread_rows_;    // Update: part t sums rows [t], [t + 1]
  PlacedDoubles partial_;  // Update: parts 1.. sum here, a coarse matrix's values each
  std::vector<int32_t> aggregate_row_begin_;  // Apply: aggregate a's rows are
  std::vector<int32_t> aggregate_rows_;       //   [begin[a], begin[a + 1]) of these
  std::vector<int32_t> own_aggregates_;       // Apply: the aggregates with rows here
  int num_threads_ = 1;
  std::unique_ptr<CholeskySolver> coarse_solver_;
  bool coarse_ok_ = false;
  mutable std::vector<double> rc_;      // R r, then the coarse solution
};

}  // namespace dba
