// Symmetric BSMC product against the dense matrix, serial and with threads
// (including the spill buffers of the multithreaded path).
#include "dba/bsmc/symmetric_multiply.h"

#include <algorithm>
#include <gtest/gtest.h>

#include <random>

#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

Eigen::VectorXd RandomVector(int64_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd x(n);
  for (int64_t i = 0; i < n; ++i) x[i] = u(rng);
  return x;
}

void ExpectMatchesDense(const BsmcMatrix& m, int threads, int min_threads_used) {
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(m);
  const Eigen::VectorXd x = RandomVector(m.num_rows(), 3);
  const Eigen::VectorXd expected = dense * x;
  Eigen::VectorXd y = Eigen::VectorXd::Constant(m.num_rows(), 1e300);  // stale garbage
  SymmetricMultiplySerial(m, x.data(), y.data());
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  const SymmetricMultiplier multiplier(m, threads);
  EXPECT_GE(multiplier.num_threads(), min_threads_used);
  Eigen::VectorXd z = Eigen::VectorXd::Constant(m.num_rows(), 1e300);
  multiplier.Multiply(x.data(), z.data());
  EXPECT_LT((z - expected).norm(), 1e-12 * expected.norm()) << threads << " threads";
  // Repeated calls give identical results (spills are cleared).
  Eigen::VectorXd z2(m.num_rows());
  multiplier.Multiply(x.data(), z2.data());
  EXPECT_EQ(z, z2);
}

TEST(SymmetricMultiply, MixedBlockSizesMatchDense) {
  testing::RandomBsmcOptions o;
  o.block_rows = 40;
  for (int threads = 1; threads <= 4; ++threads) ExpectMatchesDense(testing::MakeRandomBsmc(o), threads, 1);
}

// Large enough (> 4 · 2^17 values) that every thread gets rows, so the
// transposed products of early rows go through the spill buffers.
TEST(SymmetricMultiply, ThreadedSpillPathMatchesDense) {
  testing::RandomBsmcOptions o;
  o.block_rows = 500;
  o.sizes = {9};
  o.band = 30;
  o.fill = 0.6;
  const BsmcMatrix m = testing::MakeRandomBsmc(o);
  ASSERT_GT(m.num_values(), 4 * (int64_t{1} << 17));
  for (int threads = 2; threads <= 4; ++threads) ExpectMatchesDense(m, threads, threads);
}

TEST(SymmetricMultiply, ThreadedMixedSizesWithFarBlocks) {
  testing::RandomBsmcOptions o;
  o.block_rows = 400;
  o.sizes = {9, 6, 5};
  o.fill = 0.25;
  const BsmcMatrix m = testing::MakeRandomBsmc(o);
  ASSERT_GT(m.num_values(), 3 * (int64_t{1} << 17));
  ExpectMatchesDense(m, 3, 3);
}

// The dense matrix a mixed-precision product stands for: the diagonal
// blocks as they are, every off-diagonal value rounded to float.
Eigen::MatrixXd DenseNarrowed(const BsmcMatrix& m) {
  BsmcMatrix rounded = m;
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i) + 1; b < m.row_end(i); ++b) {
      const int n = m.block_size(i) * m.block_size(m.block_col(b));
      double* v = rounded.block_values(b);
      for (int k = 0; k < n; ++k) v[k] = static_cast<float>(v[k]);
    }
  }
  return testing::DenseFromBsmc(rounded);
}

// Narrowed in place (in rounds, with threads), the product is S's with its
// off-diagonal values rounded to float, summed in double: to 1e-12 of that
// reference, and visibly not S's own product (the test would see a value
// narrowed into the wrong place, or a diagonal block narrowed).
void ExpectMixedMatchesNarrowedDense(BsmcMatrix m, int threads) {
  const Eigen::MatrixXd exact = testing::DenseFromBsmc(m);
  const Eigen::MatrixXd narrowed = DenseNarrowed(m);
  const Eigen::VectorXd x = RandomVector(m.num_rows(), 5);
  const Eigen::VectorXd expected = narrowed * x;
  SymmetricMultiplier multiplier(m, threads, ProductPrecision::kMixed);
  const std::vector<double> formed(m.values().begin(), m.values().end());
  // Twice: the second time after S is re-formed (zeroed, filled again),
  // with the pages of S and of the diagonal copy given back in between (as
  // between LM iterations; Narrow gives back the values' rear half itself).
  for (int round = 0; round < 2; ++round) {
    if (round == 1) {
      multiplier.ReturnDiagonalPages();
      m.ZeroValuesAndReturnPages();
      m.SetZero();
      EXPECT_FALSE(m.values_narrowed());
      std::ranges::copy(formed, m.values().begin());
    }
    multiplier.Narrow(&m);
    EXPECT_TRUE(m.values_narrowed());
    Eigen::VectorXd y = Eigen::VectorXd::Constant(m.num_rows(), 1e300);
    multiplier.Multiply(x.data(), y.data());
    EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm()) << threads << " threads, round " << round;
    EXPECT_LT((y - exact * x).norm(), 1e-6 * expected.norm());
    EXPECT_GT((y - exact * x).norm(), 1e-12 * expected.norm()) << "no value was rounded";
  }
  EXPECT_GT(multiplier.MemoryBytes(), 0);
}

TEST(SymmetricMultiply, MixedPrecisionMatchesTheNarrowedMatrix) {
  testing::RandomBsmcOptions o;
  o.block_rows = 40;
  for (int threads = 1; threads <= 3; ++threads) ExpectMixedMatchesNarrowedDense(testing::MakeRandomBsmc(o), threads);
  // The camera blocks of both models, with the spill path and many rounds.
  o.block_rows = 400;
  o.sizes = {9};
  o.band = 30;
  o.fill = 0.6;
  ExpectMixedMatchesNarrowedDense(testing::MakeRandomBsmc(o), 2);
  o.sizes = {6, 5};
  o.fill = 0.3;
  ExpectMixedMatchesNarrowedDense(testing::MakeRandomBsmc(o), 2);
  // Rows with the diagonal block alone.
  o.sizes = {7};
  o.fill = 0.02;
  ExpectMixedMatchesNarrowedDense(testing::MakeRandomBsmc(o), 2);
}

// Turned to double between solves (the damping floor dropped), the product
// is the double multiplier's, bit for bit, and Narrow is refused.
TEST(SymmetricMultiply, MixedTurnedDoubleIsTheDoubleProduct) {
  testing::RandomBsmcOptions o;
  o.block_rows = 200;
  o.sizes = {9};
  o.band = 20;
  BsmcMatrix m = testing::MakeRandomBsmc(o);
  const std::vector<double> formed(m.values().begin(), m.values().end());
  const Eigen::VectorXd x = RandomVector(m.num_rows(), 7);
  SymmetricMultiplier mixed(m, 2, ProductPrecision::kMixed);
  mixed.Narrow(&m);
  mixed.UseDoublePrecision();  // after a solve, before S is re-formed
  EXPECT_EQ(mixed.precision(), ProductPrecision::kDouble);
  std::vector<double> x0(m.num_rows(), 1.0), y0(m.num_rows());
  EXPECT_THROW(mixed.Multiply(x0.data(), y0.data()), std::logic_error);  // floats
  m.SetZero();
  std::ranges::copy(formed, m.values().begin());
  EXPECT_THROW(mixed.Narrow(&m), std::logic_error);
  Eigen::VectorXd y(m.num_rows()), expected(m.num_rows());
  mixed.Multiply(x.data(), y.data());
  SymmetricMultiplier(m, 2, ProductPrecision::kDouble).Multiply(x.data(), expected.data());
  EXPECT_EQ(y, expected);
  EXPECT_LT((y - testing::DenseFromBsmc(m) * x).norm(), 1e-12 * y.norm());
}

TEST(SymmetricMultiply, MixedProductRefusesValuesNotNarrowed) {
  testing::RandomBsmcOptions o;
  o.block_rows = 10;
  BsmcMatrix m = testing::MakeRandomBsmc(o);
  SymmetricMultiplier mixed(m, 1, ProductPrecision::kMixed);
  std::vector<double> x(m.num_rows(), 1.0), y(m.num_rows());
  EXPECT_THROW(mixed.Multiply(x.data(), y.data()), std::logic_error);
  mixed.Narrow(&m);
  const SymmetricMultiplier plain(m, 1);
  EXPECT_THROW(plain.Multiply(x.data(), y.data()), std::logic_error);
  m.SetZero();  // re-formed: the mixed product must narrow again
  EXPECT_THROW(mixed.Multiply(x.data(), y.data()), std::logic_error);
  BsmcMatrix other = m;
  EXPECT_THROW(mixed.Narrow(&other), std::logic_error);
  mixed.Narrow(&m);
  EXPECT_THROW(mixed.Narrow(&m), std::logic_error);  // twice: the floats are not doubles
}

}  // namespace
}  // namespace dba
