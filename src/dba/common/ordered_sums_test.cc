// Parallel sums added in thread order: equal, bit for bit, to the same
// static ranges summed one after the other, on every repetition, for terms
// whose sum depends on the order it is taken in.
#include "dba/common/ordered_sums.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dba {
namespace {

TEST(OrderedSums, ThreadOrderEveryTime) {
  const int64_t n = 100003;
  std::vector<double> x(n);
  for (int64_t i = 0; i < n; ++i) x[i] = std::pow(-1.7, static_cast<double>(i % 37)) * (1.0 + 1e-3 * i);
  for (int threads : {2, 3, 5, 8}) {
    // The expected: OpenMP's static ranges, the first n % t one longer,
    // each summed in order, the partial sums then added in thread order.
    double expected = 0.0;
    const int64_t q = n / threads, r = n % threads;
    for (int t = 0; t < threads; ++t) {
      const int64_t begin = t * q + std::min<int64_t>(t, r), end = begin + q + (t < r ? 1 : 0);
      double partial = 0.0;
      for (int64_t i = begin; i < end; ++i) partial += x[i];
      expected += partial;
    }
    for (int repeat = 0; repeat < 20; ++repeat) {
      const auto s = ParallelSums<2>(n, threads, true, [&](int64_t i, double* acc) {
        acc[0] += x[i];
        acc[1] += 2.0 * x[i];
      });
      ASSERT_EQ(s[0], expected) << threads << " threads, repeat " << repeat;
      ASSERT_EQ(s[1], 2.0 * expected);
    }
  }
  const auto serial = ParallelSums<1>(n, 4, false, [&](int64_t i, double* acc) { acc[0] += x[i]; });
  double in_order = 0.0;
  for (double v : x) in_order += v;
  EXPECT_EQ(serial[0], in_order);
}

}  // namespace
}  // namespace dba
