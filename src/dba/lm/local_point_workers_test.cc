// The candidate points' buffer lent to PCG: only where PCG's per-solve
// storage fits in it, never to a factorization, and the solve in it takes
// the same step as in PCG's own storage.
#include "dba/lm/local_point_workers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

Problem Survey(int num_points) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 12;
  o.num_points = num_points;
  o.max_track = 5;
  o.pixel_noise = 0.5;
  o.point_perturbation = 0.05;
  o.rotation_perturbation = 0.01;
  return testing::MakeSyntheticBal(o).problem;
}

LinearSolverOptions Options(LinearSolverType type) {
  LinearSolverOptions o;
  o.type = type;
  o.pcg.relative_tolerance = 1e-12;
  o.pcg.eta = 0.0;
  return o;
}

// δc of the first LM iteration at λ, by `workers`' solver for `type`.
std::vector<double> FirstStep(LocalPointWorkers* workers, LinearSolverType type, double lambda,
                              bool* lent) {
  RcsSystem& system = workers->FormRcs(lambda);
  RcsSolverChoice choice;
  std::unique_ptr<DampedRcsSolver> solver =
      workers->MakeDampedRcsSolver(system, Options(type), &choice);
  *lent = workers->candidate_points_lent();
  std::vector<double> delta(system.S.num_rows());
  EXPECT_TRUE(solver->Solve(lambda, DampingBounds{}, &system, delta.data()).ok);
  return delta;
}

TEST(LocalPointWorkers, LendsTheCandidatePointsToPcgWhereItsStorageFits) {
  const double lambda = 1e-4;
  bool lent = false;
  // 12 cameras: PCG's per-solve storage is 12 x 81 inverses, 12 x 81 diagonal
  // copies (mixed) and 4 x 108 vector entries, 2,376 doubles; the candidate
  // points of 3,000 points are 9,000.
  Problem many = Survey(3000);
  LocalPointWorkers pcg(&many, DampingBounds{}, 2);
  const std::vector<double> in_candidates = FirstStep(&pcg, LinearSolverType::kPcg, lambda, &lent);
  EXPECT_TRUE(lent);
  // The solve wrote its storage there (the inverses are not zero).
  ASSERT_EQ(pcg.candidate_points().size(), many.points.size());
  EXPECT_GT(std::count_if(pcg.candidate_points().begin(), pcg.candidate_points().end(),
                          [](double v) { return v != 0.0; }),
            12 * 9);
  // The same step as a dense factorization, which borrows nothing.
  Problem same = Survey(3000);
  LocalPointWorkers dense(&same, DampingBounds{}, 2);
  const std::vector<double> by_dense = FirstStep(&dense, LinearSolverType::kDense, lambda, &lent);
  EXPECT_FALSE(lent);
  ASSERT_EQ(in_candidates.size(), by_dense.size());
  double diff = 0.0, norm = 0.0;
  for (size_t i = 0; i < by_dense.size(); ++i) {
    diff += (in_candidates[i] - by_dense[i]) * (in_candidates[i] - by_dense[i]);
    norm += by_dense[i] * by_dense[i];
  }
  EXPECT_LT(diff, 1e-18 * norm);
  // 300 points (900 doubles) do not hold PCG's storage: nothing is lent.
  Problem few = Survey(300);
  LocalPointWorkers small(&few, DampingBounds{}, 2);
  FirstStep(&small, LinearSolverType::kPcg, lambda, &lent);
  EXPECT_FALSE(lent);
}

}  // namespace
}  // namespace dba
