// Every RCS solver against a dense LLT of the same matrix (mixed block sizes,
// random patterns), refusal of matrices that are not positive definite, and
// the choice of auto.
#include "dba/solver/rcs_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>


#include "dba/solver/sparse_cholesky.h"
#include "dba/solver/two_level_preconditioner.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

BsmcMatrix Spd(int block_rows, double fill, int band, uint32_t seed) {
  testing::RandomBsmcOptions o;
  o.block_rows = block_rows;
  o.fill = fill;
  o.band = band;
  o.positive_definite = true;
  o.seed = seed;
  return testing::MakeRandomBsmc(o);
}

class EachSolver : public ::testing::TestWithParam<LinearSolverType> {};

TEST_P(EachSolver, SolvesLikeDenseCholesky) {
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    BsmcMatrix S = Spd(25 + 10 * seed, 0.15, seed % 2 == 0 ? 4 : 0, seed);
    LinearSolverOptions options;
    options.type = GetParam();
    options.pcg.eta = 0.0;  // a tight solve, to compare with the direct one
    options.pcg.relative_tolerance = 1e-13;
    options.num_threads = 2;
    RcsSolverChoice choice;
    std::unique_ptr<RcsSolver> solver = MakeRcsSolver(S, options, &choice);
    ASSERT_EQ(solver->type(), GetParam());
    EXPECT_EQ(choice.type, GetParam());
    // Two numeric phases on one symbolic one: values change, structure not.
    for (int round = 0; round < 2; ++round) {
      if (round == 1) {
        for (int32_t i = 0; i < S.num_block_rows(); ++i) {
          double* d = S.block_values(S.diagonal_block(i));
          for (int a = 0; a < S.block_size(i); ++a) d[a * S.block_size(i) + a] *= 1.5;
        }
      }
      const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
      const Eigen::VectorXd expected = testing::SolveSpd(dense, b);
      Eigen::VectorXd x(S.num_rows());
      const LinearSolveSummary s = solver->Solve(S, b.data(), x.data());
      ASSERT_TRUE(s.ok) << "seed " << seed << " round " << round;
      EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm())
          << "seed " << seed << " round " << round << " stop " << s.stop;
    }
  }
}

TEST_P(EachSolver, IndefiniteMatrixIsRefusedOrBreaksDown) {
  BsmcMatrix S = Spd(20, 0.3, 0, 9);
  LinearSolverOptions options;
  options.type = GetParam();
  std::unique_ptr<RcsSolver> solver = MakeRcsSolver(S, options);
  for (double& v : S.values()) v = -v;  // negative definite
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(S.num_rows());
  Eigen::VectorXd x(S.num_rows());
  const LinearSolveSummary s = solver->Solve(S, b.data(), x.data());
  if (GetParam() == LinearSolverType::kPcg) {
    EXPECT_EQ(s.stop, "breakdown");
  } else {
    EXPECT_FALSE(s.ok);
    EXPECT_EQ(s.stop, "not_positive_definite");
    EXPECT_EQ(x.norm(), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, EachSolver,
                         ::testing::Values(LinearSolverType::kDense, LinearSolverType::kSparse,
                                           LinearSolverType::kPcg),
                         [](const ::testing::TestParamInfo<LinearSolverType>& info) {
                           return std::string(LinearSolverName(info.param));
                         });

// Only auto's mixed product drops its damping floor (turning to double);
// an explicit precision and the factorizations have none to drop or keep
// it. Solves after the drop are the double product's (to the last bits: the
// vectors' alignment changes the order of the dot products' sums).
TEST(PcgSolver, OnlyAutosMixedProductDropsTheDampingFloor) {
  const BsmcMatrix formed = Spd(60, 0.15, 4, 11);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(formed.num_rows(), -1.0, 2.0);
  auto make = [&](PcgPrecision precision, BsmcMatrix* S) {
    LinearSolverOptions options;
    options.type = LinearSolverType::kPcg;
    options.pcg.precision = precision;
    options.pcg.relative_tolerance = 1e-13;
    options.pcg.eta = 1e-30;  // on (auto is mixed), but never the stop
    // Block-Jacobi: the two-level preconditioner's coarse factor goes through
    // threaded BLAS, whose sums differed between runs on a loaded machine
    // (1.9e-9 apart, as far as the mixed product's 3e-9).
    options.preconditioner = PreconditionerType::kBlockJacobi;
    return MakeRcsSolver(*S, options);
  };
  BsmcMatrix S_double = formed;
  Eigen::VectorXd x_double(formed.num_rows());
  ASSERT_TRUE(make(PcgPrecision::kDouble, &S_double)->Solve(S_double, b.data(), x_double.data()).ok);
  for (PcgPrecision precision : {PcgPrecision::kAuto, PcgPrecision::kMixed, PcgPrecision::kDouble}) {
    BsmcMatrix S = formed;
    std::unique_ptr<RcsSolver> solver = make(precision, &S);
    const bool mixed = precision != PcgPrecision::kDouble;
    EXPECT_EQ(solver->min_lambda(), mixed ? kMixedPrecisionMinLambda : 0.0);
    Eigen::VectorXd x(S.num_rows());
    ASSERT_TRUE(solver->Solve(S, b.data(), x.data()).ok);
    auto agrees = [&] { return (x - x_double).norm() < 1e-12 * x_double.norm(); };
    EXPECT_EQ(agrees(), !mixed) << PcgPrecisionName(precision);
    S.SetZero();  // re-formed, as between LM iterations
    std::ranges::copy(formed.values(), S.values().begin());
    EXPECT_EQ(solver->DropDampingFloor(), precision == PcgPrecision::kAuto);
    EXPECT_EQ(solver->min_lambda(), precision == PcgPrecision::kMixed ? kMixedPrecisionMinLambda : 0.0);
    EXPECT_FALSE(solver->DropDampingFloor());  // once
    ASSERT_TRUE(solver->Solve(S, b.data(), x.data()).ok);
    EXPECT_EQ(agrees(), precision != PcgPrecision::kMixed) << PcgPrecisionName(precision);
    EXPECT_LT((x - x_double).norm(), 1e-5 * x_double.norm());
  }
  BsmcMatrix S = formed;
  LinearSolverOptions options;
  options.type = LinearSolverType::kSparse;
  EXPECT_FALSE(MakeRcsSolver(S, options)->DropDampingFloor());
}

// A lent place holds what the solve computes afresh (the preconditioner's
// inverses, a mixed product's diagonal copy, the vectors): the step is the
// same as in the solver's own storage (to rounding: vectorized sums follow
// the vectors' alignment), the place is written, and the solve after it (not
// lent again) no longer reads it.
TEST(PcgSolver, ALentPlaceGivesTheSameStepAsItsOwnStorage) {
  const BsmcMatrix formed = Spd(60, 0.15, 4, 11);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(formed.num_rows(), -1.0, 2.0);
  for (PcgPrecision precision : {PcgPrecision::kMixed, PcgPrecision::kDouble}) {
    for (PreconditionerType preconditioner :
         {PreconditionerType::kBlockJacobi, PreconditionerType::kTwoLevel}) {
      LinearSolverOptions options;
      options.type = LinearSolverType::kPcg;
      options.preconditioner = preconditioner;
      options.coarse_aggregate_size = 8;
      options.pcg.precision = precision;
      options.pcg.relative_tolerance = 1e-10;
      BsmcMatrix S = formed;
      std::unique_ptr<RcsSolver> solver = MakeRcsSolver(S, options);
      const int64_t n = formed.num_rows();
      int64_t diagonal = 0;
      for (int32_t i = 0; i < formed.num_block_rows(); ++i) {
        diagonal += int64_t{formed.block_size(i)} * formed.block_size(i);
      }
      // The inverses, the diagonal copy (mixed), r, z, d and S d; two-level:
      // its coarse matrix.
      const int64_t coarse =
          preconditioner == PreconditionerType::kTwoLevel
              ? TwoLevelPreconditioner(formed, 8, options.pcg.num_threads).coarse().num_values()
              : 0;
      EXPECT_EQ(solver->PerSolveDoubles(),
                diagonal * (precision == PcgPrecision::kMixed ? 2 : 1) + kPcgVectors * n + coarse);
      auto solve = [&](std::vector<double>* lent) {
        S.SetZero();
        std::ranges::copy(formed.values(), S.values().begin());
        if (lent != nullptr) solver->LendForNextSolve(lent->data());
        Eigen::VectorXd x(n);
        EXPECT_TRUE(solver->Solve(S, b.data(), x.data()).ok);
        return x;
      };
      const Eigen::VectorXd own = solve(nullptr);
      std::vector<double> lent(solver->PerSolveDoubles(), std::nan(""));
      const Eigen::VectorXd in_lent = solve(&lent);
      EXPECT_LT((in_lent - own).norm(), 1e-14 * own.norm())
          << PcgPrecisionName(precision) << " " << PreconditionerName(preconditioner);
      EXPECT_EQ(std::count_if(lent.begin(), lent.end(), [](double v) { return std::isnan(v); }), 0);
      std::fill(lent.begin(), lent.end(), std::nan(""));  // the lender's again
      EXPECT_EQ(solve(nullptr), own);
    }
  }
}

TEST(AutoSolver, SmallSystemIsFactorizedDensely) {
  const BsmcMatrix S = Spd(30, 0.8, 0, 3);
  RcsSolverChoice choice;
  std::unique_ptr<RcsSolver> solver = MakeRcsSolver(S, LinearSolverOptions{}, &choice);
  EXPECT_EQ(solver->type(), LinearSolverType::kDense) << choice.reason;
  EXPECT_LE(choice.dense_bytes, 2 * choice.pcg_bytes);
}

TEST(AutoSolver, NeverExceedsTheMemoryBudget) {
  // A long band: the dense matrix is far larger than the PCG path, the sparse
  // factor of a band is not.
  const BsmcMatrix S = Spd(3000, 0.5, 3, 5);
  for (double ratio : {0.0, 2.0}) {
    LinearSolverOptions options;
    options.max_factor_memory_ratio = ratio;
    RcsSolverChoice choice;
    std::unique_ptr<RcsSolver> solver = MakeRcsSolver(S, options, &choice);
    EXPECT_NE(choice.type, LinearSolverType::kDense);
    if (ratio == 0.0) {
      EXPECT_EQ(choice.type, LinearSolverType::kPcg) << choice.reason;
    } else if (choice.type == LinearSolverType::kSparse) {
      EXPECT_LE(choice.sparse_bytes, ratio * choice.pcg_bytes);
    }
  }
}

#ifdef DBA_HAVE_CHOLMOD
// auto, with its default options, picks each solver on a system made for it:
// a small one is factorized densely, a long band (whose factor
// has no fill) sparsely, and a large one whose factor fills in is solved by
// PCG.
TEST(AutoSolver, PicksEachSolverOnASystemMadeForIt) {
  struct Case {
    BsmcMatrix S;
    LinearSolverType expected;
  };
  Case cases[] = {{Spd(30, 0.8, 0, 3), LinearSolverType::kDense},
                  {Spd(3000, 0.5, 3, 5), LinearSolverType::kSparse},
                  {Spd(3000, 0.02, 0, 7), LinearSolverType::kPcg}};
  for (const Case& c : cases) {
    RcsSolverChoice choice;
    MakeRcsSolver(c.S, LinearSolverOptions{}, &choice);
    EXPECT_EQ(LinearSolverName(choice.type), LinearSolverName(c.expected))
        << c.S.num_block_rows() << " block rows: " << choice.reason;
  }
}

// The block-graph estimate against the analysed scalar factor: a band
// (no fill beyond it) within the supernodes' explicit zeros (40%).
TEST(SparseCholesky, BlockEstimateMatchesTheFactor) {
  testing::RandomBsmcOptions o;
  o.block_rows = 400;
  o.sizes = {6};
  o.fill = 1.0;
  o.band = 3;
  o.positive_definite = true;
  const BsmcMatrix S = testing::MakeRandomBsmc(o);
  const SparseFactorEstimate e = EstimateSparseFactor(S);
  SparseCholeskySolver solver(S);
  ASSERT_TRUE(e.available);
  EXPECT_NEAR(e.factor_values, solver.factor_values(), 0.4 * solver.factor_values());
}
#endif

TEST(LinearSolverName, RoundTrips) {
  for (LinearSolverType t : {LinearSolverType::kAuto, LinearSolverType::kDense,
                             LinearSolverType::kSparse, LinearSolverType::kPcg}) {
    LinearSolverType parsed;
    ASSERT_TRUE(ParseLinearSolver(LinearSolverName(t), &parsed));
    EXPECT_EQ(parsed, t);
  }
  LinearSolverType parsed;
  EXPECT_FALSE(ParseLinearSolver("cholesky", &parsed));
}

}  // namespace
}  // namespace dba
