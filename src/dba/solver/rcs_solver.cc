// Choice and construction of the RCS solver; see rcs_solver.h.
//
// Cost model of `auto`, per LM iteration (constants measured on this 2-core
// machine, bench/README.md "Linear solvers"):
//   dense   n³/3 flops at kDenseFlopRate, n² doubles
//   sparse  the factor's flops (estimated on the block graph) at
//           kSparseFlopRate, plus a fixed cost per call
//   pcg     kTypicalPcgIterations products with S, each streaming S's values
//           and a few vectors at kStreamBandwidth
// to which the rest of the iteration (RCS formation and back-substitution,
// kSecondsPerObservation) is added. A truncated PCG step is inexact: LM
// needs more iterations with it (10 instead of 21 on problem-73-11032, where
// it also stalls 0.3% above the optimum, as Ceres's ITERATIVE_SCHUR does), so
// the PCG iteration's cost is weighed by kInexactStepPenalty. A factorization
// is a candidate only while its memory stays within max_factor_memory_ratio
// times the PCG path's.
#include "dba/solver/rcs_solver.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "dba/solver/dense_cholesky.h"
#include "dba/solver/pcg_rcs_solver.h"
#include "dba/solver/sparse_cholesky.h"

namespace dba {
namespace {

constexpr double kDenseFlopRate = 20e9;
constexpr double kSparseFlopRate = 10e9;
constexpr double kSparseCallSeconds = 2e-4;
constexpr double kStreamBandwidth = 10e9;
constexpr double kTypicalPcgIterations = 30;
constexpr double kSecondsPerObservation = 0.2e-6;
constexpr double kInexactStepPenalty = 1.5;

std::string Mib(double bytes) {
  char s[32];
  std::snprintf(s, sizeof s, "%.1f MiB", bytes / (1 << 20));
  return s;
}

}  // namespace

const char* LinearSolverName(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::kAuto: return "auto";
    case LinearSolverType::kDense: return "dense";
    case LinearSolverType::kSparse: return "sparse";
    case LinearSolverType::kPcg: return "pcg";
  }
  return "unknown";
}

const char* PreconditionerName(PreconditionerType type) {
  switch (type) {
    case PreconditionerType::kBlockJacobi: return "jacobi";
    case PreconditionerType::kTwoLevel: return "two-level";
  }
  return "unknown";
}

bool ParsePreconditioner(const std::string& name, PreconditionerType* type) {
  for (PreconditionerType t : {PreconditionerType::kBlockJacobi, PreconditionerType::kTwoLevel}) {
    if (name == PreconditionerName(t)) {
      *type = t;
      return true;
    }
  }
  return false;
}

const char* CoarseBasisName(CoarseBasis basis) {
  switch (basis) {
    case CoarseBasis::kParameters: return "parameters";
    case CoarseBasis::kRigid: return "rigid";
    case CoarseBasis::kSimilarity: return "similarity";
  }
  return "unknown";
}

bool ParseCoarseBasis(const std::string& name, CoarseBasis* basis) {
  for (CoarseBasis b : {CoarseBasis::kParameters, CoarseBasis::kRigid, CoarseBasis::kSimilarity}) {
    if (name == CoarseBasisName(b)) {
      *basis = b;
      return true;
    }
  }
  return false;
}

bool ParseLinearSolver(const std::string& name, LinearSolverType* type) {
  for (LinearSolverType t : {LinearSolverType::kAuto, LinearSolverType::kDense,
                             LinearSolverType::kSparse, LinearSolverType::kPcg}) {
    if (name == LinearSolverName(t)) {
      *type = t;
      return true;
    }
  }
  return false;
}

LinearSolveSummary CholeskySolver::Solve(BsmcMatrix& S, const double* b, double* x) {
  LinearSolveSummary summary;
  summary.stop = "factorized";
  if (!Factorize(S)) {
    summary.ok = false;
    summary.stop = "not_positive_definite";
    std::fill(x, x + S.num_rows(), 0.0);
    return summary;
  }
  SolveFactored(b, x);
  return summary;
}

std::unique_ptr<CholeskySolver> MakeCholeskySolver(const BsmcMatrix& S, int64_t max_dense_rows) {
  if (S.num_rows() <= max_dense_rows) return std::make_unique<DenseCholeskySolver>(S);
  return std::make_unique<SparseCholeskySolver>(S);
}

RcsSolverChoice ChooseRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options) {
  RcsSolverChoice choice;
  const double n = static_cast<double>(S.num_rows());
  // The budget as measured before the mixed product (its diagonal copy is
  // the memory estimate's to add: lm/memory_estimate.cc).
  choice.pcg_bytes = PcgPathBytes(S, ProductPrecision::kDouble);
  choice.dense_bytes = static_cast<int64_t>(n * n * 8);
  choice.dense_flops = n * n * n / 3;
  const double rest = kSecondsPerObservation * static_cast<double>(options.num_observations);
  choice.estimated_dense_seconds = choice.dense_flops / kDenseFlopRate + rest;
  choice.estimated_pcg_seconds =
      kInexactStepPenalty *
      (kTypicalPcgIterations * (S.ValueBytes() + 8.0 * 8.0 * n) / kStreamBandwidth + rest);
  // What a PCG solve holds: its RCS path and the problem data.
  const double budget = options.max_factor_memory_ratio *
                        static_cast<double>(choice.pcg_bytes + options.problem_bytes);
  choice.budget_bytes = static_cast<int64_t>(budget);

  choice.type = options.type;
  if (options.type != LinearSolverType::kAuto) {
    choice.reason = "chosen by option";
    if (options.type == LinearSolverType::kSparse) {
      const SparseFactorEstimate e = EstimateSparseFactor(S);
      if (e.available) {
        choice.sparse_bytes = static_cast<int64_t>(e.factor_values * 8);
        choice.sparse_flops = e.flops;
      }
    }
    return choice;
  }
  choice.type = LinearSolverType::kPcg;
  double best = choice.estimated_pcg_seconds;
  choice.reason = "the factorizations would be slower or exceed the memory budget";
  if (choice.dense_bytes <= budget && choice.estimated_dense_seconds < best) {
    choice.type = LinearSolverType::kDense;
    best = choice.estimated_dense_seconds;
    choice.reason = "dense factor " + Mib(choice.dense_bytes) + " within the budget " + Mib(budget);
  }
  // The block analysis costs an elimination tree over the camera blocks:
  // skip it where dense is already cheaper than any sparse call could be.
  if (best > kSparseCallSeconds + rest) {
    const SparseFactorEstimate e = EstimateSparseFactor(S);
    if (e.available) {
      choice.sparse_bytes = static_cast<int64_t>(e.factor_values * 8);
      choice.sparse_flops = e.flops;
      choice.estimated_sparse_seconds = e.flops / kSparseFlopRate + kSparseCallSeconds + rest;
      if (choice.sparse_bytes <= budget && choice.estimated_sparse_seconds < best) {
        choice.fallback = choice.type;
        choice.fallback_reason = choice.reason;
        choice.type = LinearSolverType::kSparse;
        choice.reason = "sparse factor " + Mib(choice.sparse_bytes) + " within the budget " +
                        Mib(budget);
      }
    }
  }
  return choice;
}

std::unique_ptr<RcsSolver> MakeRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options,
                                         RcsSolverChoice* choice_out) {
  RcsSolverChoice choice = ChooseRcsSolver(S, options);
  if (options.type == LinearSolverType::kAuto && choice.type == LinearSolverType::kSparse) {
    // The estimate picked it: the scalar analysis gives the exact factor
    // size, checked against the budget again.
    auto sparse = std::make_unique<SparseCholeskySolver>(S, options.threaded_blas ? options.num_threads : 1);
    choice.sparse_bytes = static_cast<int64_t>(sparse->factor_values() * 8);
    if (choice.sparse_bytes <= choice.budget_bytes) {
      choice.reason = "sparse factor " + Mib(choice.sparse_bytes) + " within the budget " +
                      Mib(static_cast<double>(choice.budget_bytes));
      if (choice_out != nullptr) *choice_out = choice;
      return sparse;
    }
    choice.type = choice.fallback;
    choice.reason = choice.fallback_reason;
  }
  if (choice_out != nullptr) *choice_out = choice;

  switch (choice.type) {
    case LinearSolverType::kDense: return std::make_unique<DenseCholeskySolver>(S);
    case LinearSolverType::kSparse:
      return std::make_unique<SparseCholeskySolver>(S, options.threaded_blas ? options.num_threads : 1);
    case LinearSolverType::kPcg:
    case LinearSolverType::kAuto: {
      LinearSolverOptions pcg = options;
      pcg.pcg.num_threads = options.num_threads;
      return std::make_unique<PcgRcsSolver>(S, pcg);
    }
  }
  throw std::logic_error("MakeRcsSolver: unknown solver type");
}

}  // namespace dba
