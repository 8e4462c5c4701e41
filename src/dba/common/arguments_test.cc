// Argument parsing: accepted values and the messages of refused ones.
#include "dba/common/arguments.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace dba {
namespace {

TEST(Arguments, ParsesNumbersAndIntegers) {
  EXPECT_EQ(ParseNumberArgument("--x", "1e-6"), 1e-6);
  EXPECT_EQ(ParseNumberArgument("--x", "0"), 0.0);
  EXPECT_EQ(ParseIntegerArgument("--n", "42", 1), 42);
  EXPECT_EQ(ParseIntegerArgument("--n", "3000000000", 0), 3000000000);  // past 2^31
}

TEST(Arguments, RefusesWithTheFlagAndTheValue) {
  for (const char* bad : {"", "abc", "1.5x", "nan", "inf", "-1"}) {
    try {
      ParseNumberArgument("--tol", bad);
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--tol"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos);
    }
  }
  EXPECT_THROW(ParseIntegerArgument("--n", "0", 1), std::invalid_argument);
  EXPECT_THROW(ParseIntegerArgument("--n", "2.5", 1), std::invalid_argument);
  EXPECT_THROW(ParseIntegerArgument("--n", "11", 1, 10), std::invalid_argument);
}

}  // namespace
}  // namespace dba
