// PCG with the block-Jacobi preconditioner against a dense direct solve; the
// Nash-Sofer stop against the quadratic model it tests.
#include "dba/solver/pcg.h"

#include "dba/solver/block_jacobi.h"

#include <gtest/gtest.h>

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
    const Eigen::VectorXd expected = testing::SolveSpd(dense, b);
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
  const Eigen::VectorXd expected = testing::SolveSpd(dense, b);
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

// S in one process, posing as spread over ranks (so SolvePcg takes the
// one-reduction form), counting its products and reductions.
class CountingOperator : public LocalPcgOperator {
 public:
  using LocalPcgOperator::LocalPcgOperator;
  bool SumsOverRanks() const override { return true; }
  void Multiply(const double* x, double* y) const override {
    ++products;
    LocalPcgOperator::Multiply(x, y);
  }
  void SumOverRanks(std::span<double> partial) const override {
    ++reductions;
    (void)partial;
  }
  mutable int products = 0, reductions = 0;
};

// Over ranks: one all-reduce per PCG iteration (and one to start, and one
// per residual reset), whatever stops the solve; one product per iteration,
// plus the first direction's, plus one per residual reset.
TEST(Pcg, OneReductionPerIteration) {
  const BsmcMatrix S = SpdMatrix(8);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
  Eigen::VectorXd y(S.num_rows());
  PcgScratch scratch;
  for (double eta : {0.0, 0.1}) {
    PcgOptions options;
    options.eta = eta;
    options.relative_tolerance = 1e-12;
    options.residual_reset_period = 5;
    const CountingOperator counting(multiplier);
    const PcgSummary s = SolvePcg(counting, M, b.data(), y.data(), options, &scratch);
    ASSERT_EQ(s.stop, eta > 0.0 ? PcgStop::kQuadraticModel : PcgStop::kResidual);
    ASSERT_GE(s.iterations, eta > 0.0 ? 2 : 6);
    EXPECT_EQ(counting.reductions, s.iterations + 1 + s.iterations / 5) << "eta " << eta;
    EXPECT_EQ(counting.products, s.iterations + 1 + s.iterations / 5) << "eta " << eta;
  }
}

// The one-reduction form (over ranks) takes the textbook form's iterates to
// a tight residual on an ill-conditioned system: S shifted so that its smallest
// eigenvalue is 1e-7 of its largest (a weak direction spread over every
// block, which block-Jacobi cannot see), against a textbook PCG written out
// in dense arithmetic beside it. (Chronopoulos and Gear's form, S d by
// recurrence, lost this accuracy on the fisheye problem of
// tests/cli_generate.sh.)
TEST(Pcg, TightSolveOfAnIllConditionedSystemAsTheTextbookForm) {
  BsmcMatrix S = SpdMatrix(9);
  {
    const Eigen::VectorXd eigenvalues =
        testing::EigenOfSymmetric(testing::DenseFromBsmc(S)).values;
    const double shift = eigenvalues.minCoeff() - 1e-7 * eigenvalues.maxCoeff();
    for (int32_t i = 0; i < S.num_block_rows(); ++i) {
      const int c = S.block_size(i);
      double* v = S.block_values(S.diagonal_block(i));
      for (int k = 0; k < c; ++k) v[k * c + k] -= shift;
    }
  }
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
  const SymmetricMultiplier multiplier(S, 1);
  const BlockJacobiPreconditioner M = Jacobi(S, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 2.0);
  // Textbook PCG, dense.
  Eigen::MatrixXd Minv = Eigen::MatrixXd::Zero(dense.rows(), dense.cols());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int64_t o = S.scalar_offset(i);
    const int c = S.block_size(i);
    Minv.block(o, o, c, c) = testing::Inverse(dense.block(o, o, c, c));
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), r = b, z = Minv * r, d = z;
  double rz = r.dot(z);
  int textbook = 0;
  while (r.norm() > 1e-13 * b.norm() && textbook < 500) {
    const Eigen::VectorXd Sd = dense * d;
    const double alpha = rz / d.dot(Sd);
    x += alpha * d;
    r -= alpha * Sd;
    z = Minv * r;
    const double rz_new = r.dot(z);
    d = z + (rz_new / rz) * d;
    rz = rz_new;
    ++textbook;
  }
  PcgOptions options;
  options.eta = 0.0;
  options.relative_tolerance = 1e-13;
  options.residual_reset_period = 0;
  Eigen::VectorXd y(S.num_rows());
  PcgScratch scratch;
  const PcgSummary s =
      SolvePcg(CountingOperator(multiplier), M, b.data(), y.data(), options, &scratch);
  EXPECT_EQ(s.stop, PcgStop::kResidual);
  // At this condition number the count moves with rounding (the heap's
  // alignment changes the vectorized sums' order: 42 to 53 seen, against
  // the textbook's 52); it must not be much slower.
  EXPECT_LE(s.iterations, textbook + textbook / 5);
  EXPECT_LT((y - x).norm(), 1e-6 * x.norm());
  // Both stop on their recurrences at 1e-13; the true residuals are about
  // 1.7e-11 (rounding times the condition number) and must be alike.
  const double textbook_true = (b - dense * x).norm(), ours_true = (b - dense * y).norm();
  EXPECT_LT(ours_true, 2.0 * textbook_true);
  EXPECT_LT(ours_true, 1e-10 * b.norm());
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
  const Eigen::VectorXd expected = testing::SolveSpd(block_diagonal, r);
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
