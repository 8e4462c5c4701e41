// One-process bundle adjustment of a BAL problem: LocalPointWorkers + LM.
// Thread safety: one call per problem at a time.
#pragma once

#include <functional>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/lm/levenberg_marquardt.h"
#include "dba/lm/prior_workers.h"
#include "dba/problem/problem.h"

namespace dba {

// Size of the global RCS in BSMC next to the same matrix in CSR.
struct RcsFootprint {
  int64_t block_rows = 0;
  int64_t blocks = 0;
  int64_t camera_unknowns = 0;  // scalar rows: the camera-side unknowns
  int64_t bsmc_structure_bytes = 0;
  int64_t bsmc_value_bytes = 0;
  int64_t csr_bytes = 0;  // full symmetric CSR (paper eq. 8)
  static RcsFootprint Of(const BsmcMatrix& S);
};

struct BundleAdjustSummary {
  LmSummary lm;
  double symbolic_seconds = 0.0;  // building the RCS structure
  RcsFootprint rcs;
  // With camera priors: their antenna's lever arm, as solved when refined.
  Vec3 lever_arm = Vec3::Zero();
};

// Adjusts `problem`'s cameras and points in place. `before_values`: called
// with the RCS structure before its values are allocated (RcsSystem::
// ForProblem): to estimate the solve's memory, or refuse it by throwing.
// `priors` (optional): camera-centre priors in the solve (lm/prior_workers.h);
// the costs then include theirs.
BundleAdjustSummary BundleAdjust(
    const LmOptions& options, Problem* problem,
    const std::function<void(const IterationSummary&)>& on_iteration = {},
    const std::function<void(const RcsSystem&)>& before_values = {},
    const CameraPriors* priors = nullptr);

// `total` followed by `next` (a solve after a rejection round): iterations,
// times and the log add up; the final state is next's.
void AppendSolve(const BundleAdjustSummary& next, BundleAdjustSummary* total);

}  // namespace dba
