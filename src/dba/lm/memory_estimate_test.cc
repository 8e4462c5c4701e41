// The memory estimate against the objects the solve then allocates, and the
// check that refuses a solve that would not fit.
#include "dba/lm/memory_estimate.h"

#include <gtest/gtest.h>

#include "dba/lm/bundle_adjust.h"
#include "dba/solver/pcg.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

Problem SmallProblem() {
  testing::SyntheticBalOptions o;
  o.num_cameras = 12;
  o.num_points = 300;
  o.max_track = 5;
  o.pixel_noise = 0.5;
  o.point_perturbation = 0.05;
  return testing::MakeSyntheticBal(o).problem;
}

// Each part from the structure equals what the solve allocates: S's values
// and vectors, the solver auto picks (its dense factor: n² doubles).
TEST(MemoryEstimate, PartsMatchWhatTheSolveAllocates) {
  Problem problem = SmallProblem();
  LmOptions options;
  options.num_threads = 2;
  options.max_iterations = 2;
  MemoryEstimate e;
  bool seen = false;
  const BundleAdjustSummary s = BundleAdjust(options, &problem, {}, [&](const RcsSystem& structure) {
    EXPECT_FALSE(structure.S.has_values());
    e = EstimateSolveMemory(problem, structure, options, 1000);
    seen = true;
  });
  ASSERT_TRUE(seen);
  const int64_t n = s.rcs.camera_unknowns;
  EXPECT_EQ(e.resident, 1000);
  EXPECT_EQ(e.rcs, s.rcs.bsmc_value_bytes + 3 * n * 8);
  EXPECT_EQ(e.solver, s.lm.linear_solver.type);
  ASSERT_EQ(e.solver, LinearSolverType::kDense);
  EXPECT_EQ(e.linear_solver, n * n * 8);
  // A small RCS: two threads form it in private copies.
  EXPECT_EQ(e.formation, (s.rcs.bsmc_value_bytes + 3 * n * 8));
  EXPECT_EQ(e.lm, (3 * static_cast<int64_t>(problem.cameras.size()) + n) * 8);
  EXPECT_EQ(e.candidate, static_cast<int64_t>(problem.points.size()) * 8);
  // A factorization keeps its factor: the formation phase, with the private
  // copies, is the largest.
  EXPECT_FALSE(e.solver_between_solves_returned());
  EXPECT_EQ(e.total(), e.resident + e.rcs + e.formation + e.lm + e.linear_solver);
  // PCG by option: the PCG path less S, above the block-Jacobi inverse.
  options.linear_solver.type = LinearSolverType::kPcg;
  options.num_threads = 1;
  Problem again = SmallProblem();
  BundleAdjust(options, &again, {}, [&](const RcsSystem& structure) {
    e = EstimateSolveMemory(again, structure, options, 0);
  });
  EXPECT_EQ(e.solver, LinearSolverType::kPcg);
  EXPECT_EQ(e.formation, 0);
  EXPECT_GE(e.linear_solver, 12 * 81 * 8);
  // PCG gives its storage back between solves, and the candidate points go
  // back after each step: S is held with one or the other, not both.
  EXPECT_TRUE(e.solver_between_solves_returned());
  EXPECT_FALSE(e.solve_in_candidate_points());  // 300 points hold less than PCG's storage
  EXPECT_EQ(e.growth(), e.lm + e.rcs + std::max(e.linear_solver, e.candidate));
  // Where PCG's storage fits in the candidate points' buffer, it is placed
  // there (LocalPointWorkers), and that buffer is held throughout.
  testing::SyntheticBalOptions o;
  o.num_cameras = 12;
  o.num_points = 3000;
  o.max_track = 5;
  Problem many = testing::MakeSyntheticBal(o).problem;
  BundleAdjust(options, &many, {}, [&](const RcsSystem& structure) {
    e = EstimateSolveMemory(many, structure, options, 0);
  });
  EXPECT_TRUE(e.solve_in_candidate_points());
  // Lent: the inverses (81 per camera), the mixed product's diagonal copy
  // (81) and PCG's vectors; δc is not.
  const int64_t rows = 9 * 12;
  EXPECT_EQ(e.lent, (2 * 81 * 12 + kPcgVectors * rows) * 8);
  EXPECT_EQ(e.linear_solver - e.lent, rows * 8);
  EXPECT_EQ(e.growth(), e.lm + e.rcs + e.candidate + rows * 8);
  // A point rank of a distributed solve lends nothing (its LocalPointWorkers
  // never makes a solver).
  e = EstimateSolveMemory(many, RcsSystem::ForProblem(many), options, 0, 0, EstimateRole::kForms);
  EXPECT_FALSE(e.solve_in_candidate_points());
}

TEST(MemoryEstimate, CheckRefusesWhatDoesNotFit) {
  MemoryEstimate e;
  e.resident = 100 << 20;
  e.rcs = 300 << 20;
  EXPECT_NO_THROW(CheckMemoryFits(e, -1));  // unknown: no check
  EXPECT_THROW(CheckMemoryFits(e, 0), std::runtime_error);  // a limit already reached
  EXPECT_NO_THROW(CheckMemoryFits(e, 300 << 20));
  try {
    CheckMemoryFits(e, 299 << 20);
    FAIL() << "not refused";
  } catch (const std::runtime_error& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("400.0 MiB"), std::string::npos) << what;
    EXPECT_NE(what.find("399.0 MiB is available"), std::string::npos) << what;
    EXPECT_NE(what.find("--no-memory-check"), std::string::npos) << what;
  }
}

// One check for one process and for each rank: the node's available
// memory split over the ranks on it (DBA_MEMORY_AVAILABLE, the test hook),
// heard before the refusal; a main rank's messages a forming rank's share
// of S; --no-memory-check estimates and lets it run.
TEST(MemoryEstimate, OneCheckForAProcessAndForEachRank) {
  const Problem problem = SmallProblem();
  const RcsSystem rcs = RcsSystem::ForProblem(problem);
  const LmOptions options;
  setenv("DBA_MEMORY_AVAILABLE", "4000", 1);
  MemoryCheckOptions check;
  check.ranks_on_node = 4;
  int64_t heard = 0;
  EXPECT_THROW(EstimateAndCheckMemory(problem, rcs, options, check,
                                      [&](const MemoryEstimate&, int64_t have) { heard = have; }),
               std::runtime_error);
  EXPECT_EQ(heard, 1000);
  check.refuse = false;
  check.role = EstimateRole::kSolves;
  check.forming_ranks = 3;
  const MemoryEstimate e = EstimateAndCheckMemory(problem, rcs, options, check);
  EXPECT_EQ(e.messages, rcs.S.ValueBytes() / 3);
  EXPECT_EQ(e.candidate, 0);  // the main rank holds no candidate points
  unsetenv("DBA_MEMORY_AVAILABLE");
}

}  // namespace
}  // namespace dba
