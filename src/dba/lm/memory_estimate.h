// The peak memory of a one-process solve, estimated after the symbolic phase
// and before S's values exist: what the process holds (code, the loaded
// problem, S's structure) plus what the solve will allocate, each part from
// the problem's counts and S's structure:
//
//   rcs            S's values (Σ over stored blocks of c_i c_j doubles) and
//                  b, gradient, diagonal (3 doubles per camera-side unknown)
//   formation      the threads' private copies of the RCS, where the RCS is
//                  small enough for them (rcs/form_rcs.cc)
//   lm             the candidate cameras (three copies), δc
//   candidate      the candidate points
//   linear_solver  beyond S: what auto (or the chosen solver) holds: PCG's
//                  preconditioner, vectors and diagonal copy; a dense
//                  factor n² doubles; a sparse factor: 2x the block estimate
//                  of its values (supernodes padded, CHOLMOD's workspace, the
//                  CSC copy of S: 1.8x and 2.25x measured, bench/README.md;
//                  0 without CHOLMOD: not estimated)
//   covariance     with --covariance, the analyse stage (docs/design.md §8),
//                  on top of what the solve holds: S again and CHOLMOD's
//                  copies of it (3x S's values) and the factor inverted in
//                  place (1.5x the block estimate of its values, 8 bytes
//                  each; peaks measured on generated surveys: 259 MiB
//                  against 258 estimated at 2,500 images, 1.02 GiB against
//                  1.29 GiB at 10,000)
//
// Not all of it is held at once: the candidate points from a
// back-substitution to the step's end, PCG's storage during its solve
// (their pages go back to the system in between: LocalPointWorkers::
// FinishStep, ReturnSolvePages; or PCG's storage is placed in the candidate
// points' buffer, which is then held throughout); a factorization keeps
// its factor. The
// growth is the largest of the three phases, formation, solve and
// back-substitution, over what all hold. The
// peak is the larger of that and the peak so far (loading, e.g.
// decompressing a BAL file, can pass what the solve holds).
//
// Thread safety: pure.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>

#include "dba/lm/levenberg_marquardt.h"
#include "dba/problem/problem.h"
#include "dba/rcs/form_rcs.h"

namespace dba {

struct MemoryEstimate {
  int64_t resident = 0;  // the process when estimated
  int64_t peak_so_far = 0;
  int64_t rcs = 0;
  int64_t formation = 0;
  int64_t lm = 0;
  int64_t candidate = 0;
  int64_t linear_solver = 0;
  // Distributed: the packed sub-RCS a rank sends each formation, or the
  // main rank's send and receive buffers.
  int64_t messages = 0;
  LinearSolverType solver = LinearSolverType::kPcg;

  // PCG gives its storage back between solves (ReturnSolvePages), or
  // places it in the candidate points' buffer (lent); a factorization keeps
  // its factor.
  bool solver_between_solves_returned() const {
    return solver != LinearSolverType::kDense && solver != LinearSolverType::kSparse;
  }
  // One process, PCG: the part of linear_solver placed in the candidate
  // points' buffer, idle during the solve (LocalPointWorkers::
  // MakeDampedRcsSolver, the same test less the two-level coarse matrix,
  // which the estimate leaves out: where that tips the balance, about 3% of
  // the storage, it counts a lending the solver does not make), which is
  // then held throughout; 0 where it does not fit.
  int64_t lent = 0;
  bool solve_in_candidate_points() const { return lent > 0; }
  int64_t covariance = 0;
  // What the solve adds to the process: its largest phase, then the
  // analyse stage's covariance on top.
  int64_t growth() const { return solve_growth() + covariance; }
  int64_t solve_growth() const {
    if (solve_in_candidate_points()) {
      return lm + messages + rcs + candidate + std::max(formation, linear_solver - lent);
    }
    const int64_t kept = solver_between_solves_returned() ? 0 : linear_solver;
    const int64_t formation_phase = rcs + formation + kept;
    const int64_t solve_phase = rcs + linear_solver;
    const int64_t back_substitution_phase = rcs + candidate + kept;
    return lm + messages +
           std::max({formation_phase, solve_phase, back_substitution_phase});
  }
  int64_t total() const {
    const int64_t solve = resident + growth();
    return solve > peak_so_far ? solve : peak_so_far;
  }
  // "1.23 GiB (process 0.80 GiB, RCS ..., ...)".
  std::string Describe() const;
};

// What a process does with the RCS it estimates: all of it (one process), or
// in a distributed solve forms its share's sub-RCS (a point rank: no linear
// solver; its packed sub-RCS as messages), or solves the global RCS (the
// main rank: no formation copies, no candidate points, which the point ranks
// hold; its messages are the caller's to add).
enum class EstimateRole { kWhole, kForms, kSolves };

// `structure`: the problem's RCS after the symbolic phase, values not yet
// allocated (RcsSystem::ForProblem's before_values); `resident_bytes`: the
// process's resident memory then, and its peak so far; `num_observations`:
// the solve's (auto's cost model weighs them), -1 for the problem's own (the
// main rank of a distributed solve holds none).
MemoryEstimate EstimateSolveMemory(const Problem& problem, const RcsSystem& structure,
                                   const LmOptions& options, int64_t resident_bytes,
                                   int64_t peak_so_far = 0,
                                   EstimateRole role = EstimateRole::kWhole,
                                   int64_t num_observations = -1);

// Throws std::runtime_error (saying both figures and the override) when the
// estimate's growth beyond `estimate.resident` exceeds `available_bytes`
// (what the machine, the cgroups or RLIMIT_AS leave; -1: unknown, no check;
// 0: no room at all).
void CheckMemoryFits(const MemoryEstimate& estimate, int64_t available_bytes);

// How a process checks its memory before a solve's RCS takes its values,
// one process or a rank of many: what it estimates for (`role`), and
// whether a growth past its part of the node's available memory (shared by
// the `ranks_on_node` processes on it) is refused.
struct MemoryCheckOptions {
  bool refuse = true;  // false: --no-memory-check, the estimate alone
  int ranks_on_node = 1;
  EstimateRole role = EstimateRole::kWhole;
  // kSolves: the main rank's one message buffer holds about a forming
  // rank's share of the global RCS.
  int forming_ranks = 1;
  int64_t num_observations = -1;  // EstimateSolveMemory's
  bool covariance = false;        // --covariance: the analyse stage's factor too
};
// The estimate at `structure` with the process's resident and peak memory
// now; `seen` (if any) hears it and the process's part of the available
// memory (-1: unknown) before the check refuses (CheckMemoryFits).
MemoryEstimate EstimateAndCheckMemory(
    const Problem& problem, const RcsSystem& structure, const LmOptions& options,
    const MemoryCheckOptions& check,
    const std::function<void(const MemoryEstimate&, int64_t available)>& seen = {});

// "1.5 GiB", "320.4 MiB".
std::string FormatBytes(int64_t bytes);

}  // namespace dba
