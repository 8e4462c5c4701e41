#include "dba/common/memory.h"

#include <gtest/gtest.h>

#include <vector>

namespace dba {
namespace {

TEST(Memory, PeakGrowsWithATouchedAllocation) {
  const int64_t before = PeakResidentBytes();
  ASSERT_GT(before, 0);
  std::vector<char> big(before + (64 << 20), 1);  // touches every page
  const int64_t after = PeakResidentBytes();
  EXPECT_GE(after, static_cast<int64_t>(big.size()));
  EXPECT_GE(CurrentResidentBytes(), static_cast<int64_t>(big.size()));
  EXPECT_LE(CurrentResidentBytes(), after);
}

}  // namespace
}  // namespace dba
