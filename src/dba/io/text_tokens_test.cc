// Tokens of a line and exact number parsing, shared by the BAL and COLMAP
// text readers.
#include "dba/io/text_tokens.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace dba {
namespace {

TEST(TextTokens, TokensOfALineWithEveryBlank) {
  LineTokens t(" \t1  -2.5e3\v\fname \r");
  EXPECT_EQ(t.Remaining(), 3);
  std::vector<std::string> got;
  std::string_view tok;
  while (t.Next(&tok)) got.emplace_back(tok);
  EXPECT_EQ(got, (std::vector<std::string>{"1", "-2.5e3", "name"}));
  EXPECT_TRUE(t.Done());
  LineTokens u("a b c  ");
  u.Next(&tok);
  EXPECT_EQ(u.Rest(), "b c");
}

TEST(TextTokens, NumbersWholeAndExact) {
  double d = 0;
  EXPECT_EQ(ParseDouble("+1.5", &d), NumberStatus::kOk);
  EXPECT_EQ(d, 1.5);
  EXPECT_EQ(ParseDouble("-0.1", &d), NumberStatus::kOk);
  EXPECT_EQ(d, -0.1);
  EXPECT_EQ(ParseDouble("1.5x", &d), NumberStatus::kNotANumber);
  EXPECT_EQ(ParseDouble("+-1", &d), NumberStatus::kNotANumber);
  EXPECT_EQ(ParseDouble("", &d), NumberStatus::kNotANumber);
  EXPECT_EQ(ParseDouble("1e999", &d), NumberStatus::kOutOfRange);
  EXPECT_EQ(ParseDouble("nan", &d), NumberStatus::kNotFinite);
  EXPECT_EQ(ParseDouble("-inf", &d), NumberStatus::kNotFinite);
  int64_t i = 0;
  EXPECT_EQ(ParseInteger("-9223372036854775808", &i), NumberStatus::kOk);
  EXPECT_EQ(i, INT64_MIN);
  EXPECT_EQ(ParseInteger("9223372036854775808", &i), NumberStatus::kOutOfRange);
  EXPECT_EQ(ParseInteger("3.0", &i), NumberStatus::kNotANumber);
  uint64_t u = 0;
  EXPECT_EQ(ParseInteger("18446744073709551615", &u), NumberStatus::kOk);
  EXPECT_EQ(u, UINT64_MAX);
  EXPECT_EQ(ParseInteger("-1", &u), NumberStatus::kNotANumber);
}

}  // namespace
}  // namespace dba
