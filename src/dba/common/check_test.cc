// DBA_DCHECK: with checks on, a false condition aborts naming the file, the
// line and the condition; a true one does nothing.
#define DBA_CHECKS 1
#include "dba/common/check.h"

#include <gtest/gtest.h>

namespace dba {
namespace {

TEST(DcheckTest, FalseConditionAbortsWithFileLineAndCondition) {
  const int block = -1;
  EXPECT_DEATH(DBA_DCHECK(block >= 0), "check_test.cc:[0-9]+: internal check failed: block >= 0");
}

TEST(DcheckTest, TrueConditionPasses) {
  int evaluated = 0;
  DBA_DCHECK(++evaluated == 1);
  EXPECT_EQ(evaluated, 1);
}

}  // namespace
}  // namespace dba
