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

#include "dba/solver/rcs_solver.h"

namespace dba {

// nnz and flops of the sparse factor, estimated on the block graph (cheap:
// an elimination tree over nb blocks) and scaled by the mean block size.
struct SparseFactorEstimate {
  bool available = false;  // false without CHOLMOD
  double factor_values = 0.0;
  double flops = 0.0;
};
SparseFactorEstimate EstimateSparseFactor(const BsmcMatrix& S);

// Threads of the BLAS under CHOLMOD's supernodal kernels. OpenBLAS's
// threads otherwise default to every core and busy-wait (sched_yield) next
// to dba's own: on problem-49-7776 with -t 1 that was 30% of the run. A no-op
// for a BLAS without openblas_set_num_threads.
void SetBlasThreads(int num_threads);

class SparseCholeskySolver : public CholeskySolver {
 public:
  explicit SparseCholeskySolver(const BsmcMatrix& S);
  ~SparseCholeskySolver() override;
  bool Factorize(const BsmcMatrix& S) override;
  void SolveFactored(const double* b, double* x) override;
  LinearSolverType type() const override { return LinearSolverType::kSparse; }
  int64_t MemoryBytes() const override;
  // Values in the factor as analysed.
  double factor_values() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dba
