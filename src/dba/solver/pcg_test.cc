// PCG with the block-Jacobi preconditioner against a dense direct solve; the
// Nash-Sofer stop against the quadratic model it tests.
#include "dba/solver/pcg.h"

#include "dba/solver/block_jacobi.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

BsmcMatrix SpdMatrix(uint32_t seed) {
  testing::RandomBsmcOptions o;
  o.block_rows = 30;
  o.fill = 0.3;
  o.positive_definite = true;
  o.seed = seed;
  return testing::MakeRandomBsmc(o);
}

BlockJacobiPreconditioner Jacobi(const BsmcMatrix& S, int threads) {
  BlockJacobiPreconditioner M(S, threads);
  M.Update(S);
  return M;
}

TEST(Pcg, MatchesDenseCholesky) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const BsmcMatrix S = SpdMatrix(seed);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
    const Eigen::VectorXd expected = dense.llt().solve(b);
    const SymmetricMultiplier multiplier(S, 2);
    const BlockJacobiPreconditioner M = Jacobi(S, 2);
    Eigen::VectorXd y(S.num_rows());
    PcgOptions options;
    options.relative_tolerance = 1e-12;
    options.eta = 0.0;
    options.residual_reset_period = 7;  // exercises the recomputed residual
    PcgScratch scratch;
    const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
    EXPECT_EQ(s.stop, PcgStop::kResidual) << PcgStopName(s.stop);
    EXPECT_LT((y - expected).norm(), 1e-9 * expected.norm());
    // The reported residual is the real one.
    const double real = (b - dense * y).norm() / b.norm();
    EXPECT_NEAR(s.relative_residual, real, 1e-3 * real + 1e-15);
    EXPECT_LE(real, 1e-12 * 1.01);
  }
}

// Mixed precision: PCG converges on the matrix with float off-diagonal
// values, within float's rounding of S's own solution; auto picks it only
// with the η stop.
TEST(Pcg, MixedPrecisionSolvesToFloatAccuracy) {
  BsmcMatrix S = SpdMatrix(5);
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
  const Eigen::VectorXd expected = dense.llt().solve(b);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  PcgOptions options;
  EXPECT_EQ(options.product_precision(), ProductPrecision::kMixed);  // the default: η = 0.1
  options.eta = 0.0;
  EXPECT_EQ(options.product_precision(), ProductPrecision::kDouble);
  options.precision = PcgPrecision::kMixed;
  EXPECT_EQ(options.product_precision(), ProductPrecision::kMixed);
  options.relative_tolerance = 1e-12;
  SymmetricMultiplier multiplier(S, 1, options.product_precision());
  multiplier.Narrow(&S);
  Eigen::VectorXd y(S.num_rows());
  PcgScratch scratch;
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
  EXPECT_EQ(s.stop, PcgStop::kResidual) << PcgStopName(s.stop);
  const double error = (y - expected).norm() / expected.norm();
  EXPECT_LT(error, 1e-5);
  EXPECT_GT(error, 1e-12);  // it solved the narrowed matrix, not S
}

TEST(Pcg, IterationCapIsReported) {
  const BsmcMatrix S = SpdMatrix(4);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(S.num_rows()), y(S.num_rows());
  PcgOptions options;
  options.relative_tolerance = 1e-14;
  options.max_iterations = 2;
  options.eta = 0.0;
  PcgScratch scratch;
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
  EXPECT_EQ(s.stop, PcgStop::kIterationLimit);
  EXPECT_EQ(s.iterations, 2);
  EXPECT_GT(s.relative_residual, 1e-14);
}

TEST(Pcg, ZeroRightHandSideGivesZero) {
  const BsmcMatrix S = SpdMatrix(5);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(S.num_rows());
  Eigen::VectorXd y = Eigen::VectorXd::Ones(S.num_rows());
  PcgScratch scratch;
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), PcgOptions{}, &scratch);
  EXPECT_EQ(s.stop, PcgStop::kZeroRhs);
  EXPECT_EQ(y.norm(), 0.0);
}

// Q(y) = ½ yᵀS y - bᵀy of the dense matrix.
double Quadratic(const Eigen::MatrixXd& S, const Eigen::VectorXd& b, const Eigen::VectorXd& y) {
  return 0.5 * y.dot(S * y) - b.dot(y);
}

// The truncated-Newton stop: at exit i·(Q_i - Q_{i-1})/Q_i < η, and not one
// iteration earlier (rerun with one iteration less: the test did not pass).
TEST(Pcg, NashSoferStopsWhenTheModelStopsImproving) {
  testing::RandomBsmcOptions o;
  o.block_rows = 60;
  o.fill = 0.2;
  o.positive_definite = true;
  o.seed = 11;
  const BsmcMatrix S = testing::MakeRandomBsmc(o);
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -2.0, 1.0);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  PcgScratch scratch;
  for (double eta : {0.5, 0.1, 0.01}) {
    PcgOptions options;
    options.eta = eta;
    options.relative_tolerance = 0.0;
    Eigen::VectorXd y(S.num_rows()), y_before(S.num_rows()), y_two_before(S.num_rows());
    const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
    ASSERT_EQ(s.stop, PcgStop::kQuadraticModel) << "eta " << eta;
    ASSERT_GE(s.iterations, 2) << "eta " << eta;
    options.max_iterations = s.iterations - 1;
    SolvePcg(multiplier, M, b.data(), y_before.data(), options, &scratch);
    const double q = Quadratic(dense, b, y), q_before = Quadratic(dense, b, y_before);
    EXPECT_LT(s.iterations * (q - q_before) / q, eta) << "eta " << eta;
    if (s.iterations >= 2) {
      options.max_iterations = s.iterations - 2;
      if (options.max_iterations > 0) {
        SolvePcg(multiplier, M, b.data(), y_two_before.data(), options, &scratch);
      } else {
        y_two_before.setZero();
      }
      const double q_two = Quadratic(dense, b, y_two_before);
      EXPECT_GE((s.iterations - 1) * (q_before - q_two) / q_before, eta) << "eta " << eta;
    }
  }
}

TEST(Pcg, NashSoferWaitsForTheMinimumIterations) {
  const BsmcMatrix S = SpdMatrix(5);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  PcgScratch scratch;
  PcgOptions options;
  options.eta = 1e9;  // the test passes at the first iteration that lowers Q
  options.relative_tolerance = 0.0;
  Eigen::VectorXd y(S.num_rows());
  const PcgSummary first = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
  ASSERT_EQ(first.stop, PcgStop::kQuadraticModel);
  ASSERT_EQ(first.iterations, 1);
  for (int min : {2, 7}) {
    options.min_iterations = min;
    const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
    EXPECT_EQ(s.stop, PcgStop::kQuadraticModel) << "min " << min;
    EXPECT_EQ(s.iterations, min) << "min " << min;
  }
}

TEST(BlockJacobi, AppliesTheInverseOfEachDiagonalBlock) {
  const BsmcMatrix S = SpdMatrix(6);
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
  Eigen::MatrixXd block_diagonal = Eigen::MatrixXd::Zero(dense.rows(), dense.cols());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int64_t o = S.scalar_offset(i);
    const int c = S.block_size(i);
    block_diagonal.block(o, o, c, c) = dense.block(o, o, c, c);
  }
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(S.num_rows(), 1.0, 3.0);
  const Eigen::VectorXd expected = block_diagonal.llt().solve(r);
  Eigen::VectorXd z(S.num_rows());
  Jacobi(S, 2).Apply(r.data(), z.data());
  EXPECT_LT((z - expected).norm(), 1e-10 * expected.norm());
}

TEST(BlockJacobi, IndefiniteBlockGivesFiniteOutput) {
  BsmcMatrix S = SpdMatrix(7);
  double* d = S.block_values(S.diagonal_block(0));
  for (int k = 0; k < S.block_size(0) * S.block_size(0); ++k) d[k] = -1.0;
  Eigen::VectorXd r = Eigen::VectorXd::Ones(S.num_rows()), z(S.num_rows());
  Jacobi(S, 1).Apply(r.data(), z.data());
  EXPECT_TRUE(z.allFinite());
}

}  // namespace
}  // namespace dba
