// Sparse Cholesky solve of the damped RCS, P S Pᵀ = L Lᵀ, for medium systems.
//
// Symbolic phase, once per LM solve: a fill-reducing order of the camera
// blocks (AMD on the block graph, nb nodes instead of n scalars, as Ceres
// orders SPARSE_SCHUR), expanded to scalars; the scalar pattern of S's upper
// triangle in compressed columns; the supernodal analysis (CHOLMOD) in that
// order. Numeric phase, per LM iteration: S's values gathered from BSMC into
// the pattern (no triplets, no sort), a supernodal refactorization, two
// triangular solves.
//
// Built with -DDBA_CHOLMOD=OFF (CHOLMOD's supernodal module is GPL) the same
// interface runs Eigen's SimplicialLLT with AMD ordering instead.
//
// Thread safety: one Solve at a time.
#pragma once

#include <memory>
#include <vector>

#include "dba/solver/rcs_solver.h"
#include "dba/solver/selected_inversion.h"

namespace dba {

// nnz and flops of the sparse factor, estimated on the block graph (cheap:
// an elimination tree over nb blocks) and scaled by the mean block size.
struct SparseFactorEstimate {
  bool available = false;  // false without CHOLMOD
  double factor_values = 0.0;
  double flops = 0.0;
};
SparseFactorEstimate EstimateSparseFactor(const BsmcMatrix& S);

// The fill-reducing order of S's camera blocks: approximate minimum degree
// (the LM's solves: quick to find), or nested dissection by METIS through
// CHOLMOD (less fill and fewer flops on a survey's graph: a 10,000-image
// one's factor 80M values and 3.1e11 inversion flops against AMD's 93M and
// 4.7e11; the covariance's factor, analysed once). Without CHOLMOD, Eigen's
// AMD on the scalars either way.
enum class BlockOrdering { kAmd, kNestedDissection };

class SparseCholeskySolver : public CholeskySolver {
 public:
  // `blas_threads`: the BLAS threads of CHOLMOD's factorization and solves
  // (common/blas_threads.h), used only for a factor of at least 1e10 flops.
  // OpenBLAS's threads meet at a spinning barrier after every call, so a
  // loaded core stalls them all: with two busy processes beside it, 2 BLAS
  // threads took 13.3 s instead of 0.9 s for 8 factorizations of 6.4e8
  // flops, and 43.7 s instead of 5.0 s for 2 of 4.1e10. On a quiet machine
  // they gain 8% at 6.4e8 flops, 25% at 6.8e9 and 35% at 4.1e10
  // (bench/README.md, "BLAS threads").
  explicit SparseCholeskySolver(const BsmcMatrix& S, int blas_threads = 1,
                                BlockOrdering ordering = BlockOrdering::kAmd);
  ~SparseCholeskySolver() override;
  bool Factorize(const BsmcMatrix& S) override;
  // Factorize of S with the rows and columns flagged in `rows` (one flag per
  // scalar row) made the identity's, without a copy of S.
  bool FactorizeWithIdentityRows(const BsmcMatrix& S, std::vector<uint8_t> rows);
  // After a Factorize that returned false: the row of S whose pivot was not
  // positive (CHOLMOD's; -1 when unknown).
  int64_t failed_row() const { return failed_row_; }
  void SolveFactored(const double* b, double* x) override;
  // X = S⁻¹ B for `columns` right-hand sides at once (column-major n ×
  // columns): one pass over the factor for all of them.
  void SolveFactoredColumns(const double* B, int columns, double* X);
  LinearSolverType type() const override { return LinearSolverType::kSparse; }
  int64_t MemoryBytes() const override;
  // Values in the factor as analysed.
  double factor_values() const;
  // The last factorization's L (P S Pᵀ = L Lᵀ) by supernodes, for
  // selected inversion (solver/selected_inversion.h), its values where
  // the factorization left them (with CHOLMOD, not copied). The solver is
  // spent: nothing but its destruction may follow.
  SupernodalFactor TakeFactor();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int blas_threads_ = 1;
  std::vector<uint8_t> identity_rows_;  // FactorizeWithIdentityRows's, while it runs
  int64_t failed_row_ = -1;
};

}  // namespace dba
