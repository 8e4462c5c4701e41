// End to end on every real BAL problem in ../shared/data/bal: the default
// options reach the exact final cost (from a direct sparse Schur
// factorization) within 0.1%, and 1 and 2 threads agree to 1e-9.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dba/io/bal_reader.h"
#include "dba/lm/bundle_adjust.h"

namespace dba {
namespace {

struct Case {
  const char* file;
  double exact_final_cost;
};

class BalProblemsTest : public ::testing::TestWithParam<Case> {};

TEST_P(BalProblemsTest, DefaultsReachTheExactCostWithAnyThreadCount) {
  const Case c = GetParam();
  const std::string path = std::string(DBA_SHARED_DATA_DIR) + "/bal/" + c.file;
  double final_cost[2];
  for (int threads = 1; threads <= 2; ++threads) {
    BalProblem problem = ReadBal(path);
    LmOptions options;
    options.num_threads = threads;
    const LmSummary s = BundleAdjust(options, &problem).lm;
    EXPECT_LE(std::abs(s.final_cost - c.exact_final_cost), 1e-3 * c.exact_final_cost)
        << c.file << " with " << threads << " threads: final cost " << s.final_cost
        << " after " << s.iterations << " iterations ("
        << TerminationReasonName(s.termination) << ")";
    final_cost[threads - 1] = s.final_cost;
  }
  EXPECT_LE(std::abs(final_cost[0] - final_cost[1]), 1e-9 * final_cost[0])
      << "1 thread: " << final_cost[0] << ", 2 threads: " << final_cost[1];
}

INSTANTIATE_TEST_SUITE_P(
    Shared, BalProblemsTest,
    ::testing::Values(Case{"balbianello-5-544-from-bundler.txt.bz2", 1.251696e+02},
                      Case{"problem-16-22106-pre.txt.bz2", 1.803390e+04},
                      Case{"problem-21-11315-pre.txt.bz2", 3.037864e+04},
                      Case{"problem-49-7776-pre.txt.bz2", 1.334432e+04},
                      Case{"problem-73-11032-pre.txt.bz2", 1.709949e+04}),
    [](const auto& info) {
      std::string name = info.param.file;
      name = name.substr(0, name.find(".txt"));
      for (char& ch : name) if (ch == '-') ch = '_';
      return name;
    });

}  // namespace
}  // namespace dba
