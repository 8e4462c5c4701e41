// PCG with the block-Jacobi preconditioner against a dense direct solve.
#include "dba/solver/pcg.h"

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

TEST(Pcg, MatchesDenseCholesky) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const BsmcMatrix S = SpdMatrix(seed);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
    const Eigen::VectorXd expected = dense.llt().solve(b);
    const SymmetricMultiplier multiplier(S, 2);
    const BlockJacobiPreconditioner M(S, 2);
    Eigen::VectorXd y(S.num_rows());
    PcgOptions options;
    options.relative_tolerance = 1e-12;
    const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options);
    EXPECT_TRUE(s.converged) << s.message;
    EXPECT_LT((y - expected).norm(), 1e-9 * expected.norm());
    // The reported residual is the real one.
    const double real = (b - dense * y).norm() / b.norm();
    EXPECT_NEAR(s.relative_residual, real, 1e-3 * real + 1e-15);
    EXPECT_LE(real, 1e-12 * 1.01);
  }
}

TEST(Pcg, IterationCapIsReported) {
  const BsmcMatrix S = SpdMatrix(4);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M(S, 1);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(S.num_rows()), y(S.num_rows());
  PcgOptions options;
  options.relative_tolerance = 1e-14;
  options.max_iterations = 2;
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options);
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.iterations, 2);
  EXPECT_GT(s.relative_residual, 1e-14);
}

TEST(Pcg, ZeroRightHandSideGivesZero) {
  const BsmcMatrix S = SpdMatrix(5);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M(S, 1);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(S.num_rows());
  Eigen::VectorXd y = Eigen::VectorXd::Ones(S.num_rows());
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), PcgOptions{});
  EXPECT_TRUE(s.converged);
  EXPECT_EQ(y.norm(), 0.0);
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
  BlockJacobiPreconditioner(S, 2).Apply(r.data(), z.data());
  EXPECT_LT((z - expected).norm(), 1e-10 * expected.norm());
}

TEST(BlockJacobi, IndefiniteBlockGivesFiniteOutput) {
  BsmcMatrix S = SpdMatrix(7);
  double* d = S.block_values(S.diagonal_block(0));
  for (int k = 0; k < S.block_size(0) * S.block_size(0); ++k) d[k] = -1.0;
  Eigen::VectorXd r = Eigen::VectorXd::Ones(S.num_rows()), z(S.num_rows());
  BlockJacobiPreconditioner(S, 1).Apply(r.data(), z.data());
  EXPECT_TRUE(z.allFinite());
}

}  // namespace
}  // namespace dba
