// Solvers of the damped reduced camera system S δc = b (paper eq. 4, 6-7),
// one interface for the direct factorizations and PCG, and the choice among
// them.
//
// Lifecycle: MakeRcsSolver(S) once per LM solve, from S's structure (the
// symbolic phase: orderings, fill, storage); then Solve(S, b, x) once per LM
// iteration with S's current values (the numeric phase). S keeps its
// structure between calls and must be the matrix given at construction.
//
//   dense   Cholesky of S expanded from BSMC's upper triangle (Eigen LLT);
//           n³/3 flops, n² doubles: small RCSs.
//   sparse  supernodal Cholesky (CHOLMOD) in a fill-reducing order of the
//           camera blocks (AMD on the block graph), analysed once,
//           refactorized per iteration: medium RCSs.
//   pcg     truncated-Newton PCG (solver/pcg.h) with a block-Jacobi
//           preconditioner: large RCSs; memory of S alone.
//   auto    the cheapest by the cost model in rcs_solver.cc, within a
//           memory budget.
//
// Thread safety: one Solve at a time per solver.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/solver/coarse_row_basis.h"
#include "dba/solver/pcg.h"

namespace dba {

enum class LinearSolverType { kAuto, kDense, kSparse, kPcg };
const char* LinearSolverName(LinearSolverType type);
// "auto", "dense", "sparse", "pcg"; false if `name` is none of them.
bool ParseLinearSolver(const std::string& name, LinearSolverType* type);
// For test output.
inline void PrintTo(LinearSolverType type, std::ostream* out) { *out << LinearSolverName(type); }

// PCG's preconditioner: block-Jacobi (paper eq. 7), or two-level (block-
// Jacobi plus a coarse correction over aggregated cameras, solver/
// two_level_preconditioner.h).
enum class PreconditionerType { kBlockJacobi, kTwoLevel };
const char* PreconditionerName(PreconditionerType type);
// "jacobi", "two-level"; false if `name` is neither.
bool ParsePreconditioner(const std::string& name, PreconditionerType* type);

// The two-level preconditioner's coarse coordinates per camera: the same
// parameter step for the cameras of an aggregate, the same rigid motion of
// the scene, or the same similarity (rigid motion and scale); see
// rcs/rigid_motion_basis.h.
enum class CoarseBasis { kParameters, kRigid, kSimilarity };
const char* CoarseBasisName(CoarseBasis basis);
// "parameters", "rigid", "similarity"; false if `name` is none of them.
bool ParseCoarseBasis(const std::string& name, CoarseBasis* basis);

struct LinearSolverOptions {
  LinearSolverType type = LinearSolverType::kAuto;
  PcgOptions pcg;
  PreconditionerType preconditioner = PreconditionerType::kTwoLevel;
  int coarse_aggregate_size = 64;  // two-level: cameras per aggregate
  // two-level: what the cameras of an aggregate share.
  CoarseBasis coarse_basis = CoarseBasis::kSimilarity;
  // two-level: per block row of S, the coordinates its aggregate shares
  // (filled by the caller, who knows the cameras, unless kParameters);
  // empty: the identity for all.
  std::vector<CoarseRowBasis> coarse_row_bases;
  // two-level: S's block rows in the order the aggregation visits them
  // (rcs/aggregation_order.h); empty: row order.
  std::vector<int32_t> aggregation_order;
  // auto: a factorization is chosen only while its factor stays within this
  // multiple of what a PCG solve holds: S, preconditioner, PCG vectors and
  // `problem_bytes`.
  double max_factor_memory_ratio = 2.0;
  // The problem data the solve holds anyway (observations, parameters).
  int64_t problem_bytes = 0;
  // Observations of the problem (auto's cost model weighs the linear solve
  // against the rest of an LM iteration); 0: unknown.
  int64_t num_observations = 0;
  int num_threads = 1;
  // false: CHOLMOD on one BLAS thread whatever the factor's size, for a
  // process that shares its node with others that busy-wait (MPI ranks);
  // see sparse_cholesky.h.
  bool threaded_blas = true;
};

struct LinearSolveSummary {
  int iterations = 0;        // PCG iterations; 0 for a factorization
  double relative_residual = 0.0;  // PCG's ‖r‖/‖b‖; 0 for a factorization
  std::string stop;          // PCG's stop reason, or "factorized"
  bool ok = true;            // false: S was not positive definite
};

class RcsSolver {
 public:
  virtual ~RcsSolver() = default;
  // x = S⁻¹ b (PCG: approximately). S: the matrix given at construction,
  // damped, current values. A mixed-precision PCG narrows S's values in
  // place (bsmc/symmetric_multiply.h): after Solve they are to be re-formed,
  // not read.
  virtual LinearSolveSummary Solve(BsmcMatrix& S, const double* b, double* x) = 0;
  virtual LinearSolverType type() const = 0;
  // Bytes held by the solver beyond S (factor, copies, vectors).
  virtual int64_t MemoryBytes() const = 0;
  // The least damping λ at which its solves are reliable: 0, except for a
  // mixed-precision PCG (solver/pcg.h, kMixedPrecisionMinLambda).
  virtual double min_lambda() const { return 0.0; }
  // Lowers min_lambda to 0 for the solves to come, when it can: a PCG whose
  // product is mixed by PcgPrecision::kAuto turns to a double product
  // (twice the bytes per product). True if it did.
  virtual bool DropDampingFloor() { return false; }
  // What each Solve computes afresh and forgets after it (PCG: the
  // preconditioner's values, a mixed product's diagonal copy, the vectors),
  // in doubles; 0 for a factorization, whose factor is kept.
  virtual int64_t PerSolveDoubles() const { return 0; }
  // The next Solve puts that in `place` (PerSolveDoubles() doubles, lent by
  // the caller for the solve, contents lost) instead of storage of its own;
  // the Solve after it in its own again unless lent again.
  virtual void LendForNextSolve(double* place) { (void)place; }
};

// A direct solver: Solve = Factorize, then SolveFactored. The split lets a
// preconditioner factorize once and solve many times.
class CholeskySolver : public RcsSolver {
 public:
  // Numeric factorization of S's current values; false if S is not
  // (numerically) positive definite.
  virtual bool Factorize(const BsmcMatrix& S) = 0;
  // x = S⁻¹ b with the last successful factorization; x may alias b.
  virtual void SolveFactored(const double* b, double* x) = 0;

  LinearSolveSummary Solve(BsmcMatrix& S, const double* b, double* x) final;
};

// A direct solver for S: dense up to `max_dense_rows` unknowns, sparse above
// (without CHOLMOD: dense up to 4x that, then Eigen's simplicial sparse).
std::unique_ptr<CholeskySolver> MakeCholeskySolver(const BsmcMatrix& S, int64_t max_dense_rows);

// What auto chose and why (also filled for an explicit choice).
struct RcsSolverChoice {
  LinearSolverType type = LinearSolverType::kPcg;
  std::string reason;
  int64_t pcg_bytes = 0;          // PCG path: S + preconditioner + vectors
  int64_t budget_bytes = 0;       // largest factor auto may choose
  int64_t dense_bytes = 0;        // n² doubles
  int64_t sparse_bytes = -1;      // factor + CSC copy of S; -1: not estimated
  double dense_flops = 0.0;
  double sparse_flops = -1.0;
  // Estimated seconds per LM iteration with each solver (sparse -1: not
  // estimated).
  double estimated_pcg_seconds = 0.0, estimated_dense_seconds = 0.0,
         estimated_sparse_seconds = -1.0;
  // auto's choice were sparse's exact factor over the budget.
  LinearSolverType fallback = LinearSolverType::kPcg;
  std::string fallback_reason;
};

// What MakeRcsSolver would build for S's structure (values not needed), by
// the estimates alone: a sparse choice is confirmed (or not) by the exact
// analysis only when the solver is built.
RcsSolverChoice ChooseRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options);

// Builds the solver for S's structure (options.type, or the choice of auto).
std::unique_ptr<RcsSolver> MakeRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options,
                                         RcsSolverChoice* choice = nullptr);

}  // namespace dba
