// The peak memory of a one-process solve; see memory_estimate.h.
#include "dba/lm/memory_estimate.h"

#include <cstdio>
#include <stdexcept>

#include "dba/common/memory.h"
#include "dba/common/shared_library.h"
#include "dba/solver/pcg_rcs_solver.h"
#include "dba/solver/rcs_solver.h"
#include "dba/solver/sparse_cholesky.h"

namespace dba {

std::string FormatBytes(int64_t bytes) {
  char s[32];
  const double b = static_cast<double>(bytes);
  if (b >= double(int64_t{1} << 30)) {
    std::snprintf(s, sizeof s, "%.2f GiB", b / double(int64_t{1} << 30));
  } else {
    std::snprintf(s, sizeof s, "%.1f MiB", b / double(1 << 20));
  }
  return s;
}

std::string MemoryEstimate::Describe() const {
  return FormatBytes(total()) + " (process " + FormatBytes(resident) + ", RCS " + FormatBytes(rcs) +
         ", formation copies " + FormatBytes(formation) + ", LM vectors " + FormatBytes(lm) +
         (candidate > 0 ? ", candidate points " + FormatBytes(candidate) : std::string()) +
         (messages > 0 ? ", messages " + FormatBytes(messages) : std::string()) +
         (linear_solver > 0 ? ", " + std::string(LinearSolverName(solver)) + " solver " +
                                  FormatBytes(linear_solver)
                            : std::string()) +
         (covariance > 0 ? ", covariance " + FormatBytes(covariance) : std::string()) + ")";
}

void CheckMemoryFits(const MemoryEstimate& estimate, int64_t available_bytes) {
  // Only the growth counts: a higher peak so far is behind us.
  if (available_bytes < 0 || estimate.growth() <= available_bytes) return;
  throw std::runtime_error(std::string(estimate.covariance > 0 ? "the solve and --covariance need about "
                                                               : "the solve needs about ") +
                           estimate.Describe() + " but " +
                           FormatBytes(estimate.resident + available_bytes) +
                           " is available; --no-memory-check starts it anyway");
}

MemoryEstimate EstimateAndCheckMemory(
    const Problem& problem, const RcsSystem& structure, const LmOptions& options,
    const MemoryCheckOptions& check, const std::function<void(const MemoryEstimate&, int64_t)>& seen) {
  MemoryEstimate estimate =
      EstimateSolveMemory(problem, structure, options, CurrentResidentBytes(), PeakResidentBytes(),
                          check.role, check.num_observations);
  if (check.role == EstimateRole::kSolves) {
    estimate.messages = structure.S.ValueBytes() / std::max(1, check.forming_ranks);
  }
  if (check.covariance) {
    const SparseFactorEstimate factor = EstimateSparseFactor(structure.S);
    estimate.covariance =
        factor.available ? static_cast<int64_t>(1.5 * 8 * factor.factor_values) + 3 * structure.S.ValueBytes() : 0;
  }
  const int64_t node = AvailableMemoryBytes();
  const int64_t available = node < 0 ? node : node / std::max(1, check.ranks_on_node);
  if (seen) seen(estimate, available);
  if (check.refuse) CheckMemoryFits(estimate, available);
  return estimate;
}

MemoryEstimate EstimateSolveMemory(const Problem& problem, const RcsSystem& structure,
                                   const LmOptions& options, int64_t resident_bytes,
                                   int64_t peak_so_far, EstimateRole role,
                                   int64_t num_observations) {
  const BsmcMatrix& S = structure.S;
  const int64_t rows = S.num_rows();
  MemoryEstimate e;
  e.resident = resident_bytes;
  e.peak_so_far = peak_so_far;
  e.rcs = S.ValueBytes() + 3 * rows * 8;
  if (role != EstimateRole::kSolves) {
    e.formation = std::max(FormationCopyBytes(S.num_values(), rows, options.num_threads),
                           FormationSeamBytesLimit(S.num_values(), rows, options.num_threads));
  }
  // The LM's cameras and candidate, the workers' candidate, δc; the
  // candidate points (where the points are).
  e.lm = (3 * static_cast<int64_t>(problem.cameras.size()) + rows) * 8;
  if (role != EstimateRole::kSolves) e.candidate = static_cast<int64_t>(problem.points.size()) * 8;
  if (role == EstimateRole::kForms) {
    e.messages = e.rcs + 5 * 8;  // values, b, gradient, diagonal, 5 scalars
    return e;
  }
  const LinearSolverOptions linear = LinearSolverOptionsFor(
      options, num_observations >= 0 ? num_observations : problem.num_observations());
  // The choice can load the sparse solver's libraries (CHOLMOD, LAPACK,
  // OpenBLAS: about 8 MiB resident, common/shared_library.h): the process's.
  const int64_t libraries = SharedLibrariesResidentBytes();
  const RcsSolverChoice choice = ChooseRcsSolver(S, linear);
  e.resident += SharedLibrariesResidentBytes() - libraries;
  e.solver = choice.type;
  switch (choice.type) {
    case LinearSolverType::kDense: e.linear_solver = choice.dense_bytes; break;
    case LinearSolverType::kSparse:
      // Twice the block estimate of the factor (see the header); without
      // CHOLMOD (Eigen's simplicial factorization) not estimated.
      e.linear_solver = choice.sparse_bytes >= 0 ? 2 * choice.sparse_bytes : 0;
      break;
    case LinearSolverType::kPcg:
    case LinearSolverType::kAuto:
      // Preconditioner, vectors, the diagonal copy: the PCG path less S.
      e.linear_solver = PcgPathBytes(S, linear.pcg.product_precision()) - S.ValueBytes() -
                        S.StructureBytes();
      if (role == EstimateRole::kWhole) {
        const int64_t per_solve = PcgSolveDoubles(S, linear.pcg.product_precision());
        if (per_solve <= static_cast<int64_t>(problem.points.size())) e.lent = per_solve * 8;
      }
      break;
  }
  return e;
}

}  // namespace dba
