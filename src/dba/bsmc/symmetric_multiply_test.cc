// Symmetric BSMC product against the dense matrix, serial and with threads
// (including the spill buffers of the multithreaded path).
#include "dba/bsmc/symmetric_multiply.h"

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

}  // namespace
}  // namespace dba
