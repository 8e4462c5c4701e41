// The option table's parser and values: accepted values, the messages of
// refused ones (naming the flag and the value), repeats, help wrapping.
#include "dba/common/option_table.h"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

#include "dba/common/arguments.h"

namespace dba {
namespace {

TEST(OptionTable, ParsesNumbersAndIntegersInTheirRanges) {
  EXPECT_EQ(OptionNumber("--x", "1e-6", 0, 1), 1e-6);
  EXPECT_EQ(OptionNumber("--x", "0", 0, 1), 0.0);
  EXPECT_EQ(OptionInteger("--n", "42", 1, 100), 42);
  EXPECT_EQ(OptionInteger("--n", "3000000000", 0, int64_t{1} << 40), 3000000000);  // past 2^31
  EXPECT_EQ(ParseSigmaPair("--s", "0.5,2"), std::make_pair(0.5, 2.0));
  EXPECT_EQ(ParseSigmaPair("--s", "3"), std::make_pair(3.0, 3.0));
}

TEST(OptionTable, RefusesWithTheFlagAndTheValue) {
  for (const char* bad : {"", "abc", "1.5x", "nan", "inf", "-1", "2"}) {
    try {
      OptionNumber("--tol", bad, 0, 1);
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--tol"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos);
    }
  }
  EXPECT_THROW(OptionNumber("--x", "0", 0, 1, true), std::invalid_argument);  // (0, 1]
  EXPECT_THROW(OptionInteger("--n", "0", 1, 10), std::invalid_argument);
  EXPECT_THROW(OptionInteger("--n", "2.5", 1, 10), std::invalid_argument);
  EXPECT_THROW(OptionInteger("--n", "11", 1, 10), std::invalid_argument);
  EXPECT_THROW(ParseSigmaPair("--s", "0,1"), std::invalid_argument);
  EXPECT_THROW(ParseSigmaPair("--s", "1,1e300"), std::invalid_argument);
  EXPECT_THROW(ParseSigmaPair("--s", "1e-300,1"), std::invalid_argument);
  try {
    OptionChoice("--mode", "c", {"a", "b"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--mode: expected a or b, got 'c'");
  }
}

struct Toy {
  int n = 3;
  bool flag = false;
  int size = 1;
  std::vector<std::string> words;
  std::vector<std::string> positional;
};

std::vector<OptionSpec<Toy>> ToyTable() {
  std::vector<OptionSpec<Toy>> t;
  t.push_back(IntegerOption<Toy>("--n", "N", "a count that is long enough to be wrapped over "
                                 "more than one line of the help, as most are",
                                 [](auto& o) -> auto& { return o.n; }, 0, 9));
  t.push_back(FlagOption<Toy>("--flag", "a flag", [](auto& o) -> auto& { return o.flag; }));
  OptionSpec<Toy> word = OptionEntry<Toy>("--word", OptionKind::kText, "W", "repeatable");
  word.repeatable = true;
  word.set = [](Toy& o, const std::string& v) { o.words.push_back(v); };
  t.push_back(word);
  t.back().alias = "-w";
  t.push_back(IntegerOption<Toy>("--size", "S", "its size",
                                 [](auto& o) -> auto& { return o.size; }, 1, 9));
  SetNeeds(&t.back(), "--flag or a --word", [](const Toy& o) { return o.flag || !o.words.empty(); });
  return t;
}

TEST(OptionTable, ParsesByTheTable) {
  Toy toy;
  bool help = false;
  ParseOptions(ToyTable(), {"a", "--n", "5", "-w", "x", "--flag", "--word", "y", "b"}, &toy,
               [&](const std::string& p) { toy.positional.push_back(p); }, &help, "toy");
  EXPECT_EQ(toy.n, 5);
  EXPECT_TRUE(toy.flag);
  EXPECT_EQ(toy.words, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(toy.positional, (std::vector<std::string>{"a", "b"}));
  const auto refused = [](std::vector<std::string> args, const char* says) {
    Toy t;
    bool h = false;
    try {
      ParseOptions(ToyTable(), args, &t, [](const std::string&) {}, &h, "toy");
      ADD_FAILURE() << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused({"--n", "1", "--n", "2"}, "--n: given twice");
  refused({"--n"}, "--n: missing value");
  refused({"--n", ""}, "--n: an empty value");
  refused({"--bogus"}, "unknown option '--bogus' (see dba toy --help)");
  ParseOptions(ToyTable(), {"--n", "1", "-h", "--n", "x"}, &toy, [](const std::string&) {}, &help,
               "toy");
  EXPECT_TRUE(help);
}

// An option given without what it needs is refused by name, wherever the
// need comes in the arguments; never given, it needs nothing.
TEST(OptionTable, AnOptionWithoutWhatItNeedsIsRefused) {
  const auto parse = [](std::vector<std::string> args) {
    Toy t;
    bool h = false;
    ParseOptions(ToyTable(), args, &t, [&](const std::string& p) { t.positional.push_back(p); },
                 &h, "toy");
    return t;
  };
  try {
    parse({"a", "--size", "4"});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--size needs --flag or a --word");
  }
  EXPECT_EQ(parse({"--size", "4", "-w", "x"}).size, 4);
  EXPECT_EQ(parse({"--flag", "--size", "5"}).size, 5);
  EXPECT_EQ(parse({"--n", "2"}).n, 2);
}

// After "--" every argument is positional: a path may start with '-'.
TEST(OptionTable, AfterTwoDashesEverythingIsPositional) {
  Toy toy;
  bool help = false;
  ParseOptions(ToyTable(), {"--n", "4", "--", "-w", "--help", "--"}, &toy,
               [&](const std::string& p) { toy.positional.push_back(p); }, &help, "toy");
  EXPECT_EQ(toy.n, 4);
  EXPECT_FALSE(help);
  EXPECT_TRUE(toy.words.empty());
  EXPECT_EQ(toy.positional, (std::vector<std::string>{"-w", "--help", "--"}));
}

TEST(OptionTable, HelpWrapsAndShowsDefaults) {
  std::ostringstream out;
  PrintOptions(ToyTable(), Toy(), out);
  EXPECT_NE(out.str().find("  --n N                      a count"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("(default 3)"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("  -w, --word W"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("its size (needs --flag or a --word; default 1)"), std::string::npos)
      << out.str();
  EXPECT_NE(OptionsMarkdown(ToyTable(), Toy()).find("| its size (needs --flag or a --word) |"),
            std::string::npos);
  std::istringstream lines(out.str());
  for (std::string line; std::getline(lines, line);) EXPECT_LE(line.size(), 80u) << line;
}

}  // namespace
}  // namespace dba
