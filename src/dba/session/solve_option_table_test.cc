// One declaration of `dba solve`'s options: every option of the table is in
// --help, is accepted by the parser with a value of its kind and refused
// outside its range, and README.md's table is the one the table makes.
#include "dba/session/solve_option_table.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

// A value of the option's kind that the parser accepts.
std::string GoodValue(const OptionSpec<SolveOptions>& s) {
  switch (s.kind) {
    case OptionKind::kFlag: return "";
    case OptionKind::kInteger: return std::to_string(static_cast<int64_t>(s.max));
    case OptionKind::kNumber: return OptionNumberText(s.max);
    case OptionKind::kChoice: return s.choices.back();
    case OptionKind::kList: return "0,3";
    case OptionKind::kPath: return "some/file";
    case OptionKind::kText:
      if (s.name == "--prior-sigma") return "0.5,1";
      if (s.name == "--fix-intrinsics") return "f,k1";
      if (s.name == "--lever-arm") return "0.1,-0.2,0.3";
      if (s.name == "--rig-geometry") return "fixed:1,2";
      return "EPSG:4979";
  }
  return "";
}

TEST(SolveOptionTable, EveryOptionIsInTheHelpAndParses) {
  std::ostringstream help;
  PrintSolveHelp(help);
  for (const OptionSpec<SolveOptions>& s : SolveOptionTable()) {
    EXPECT_NE(help.str().find(s.name), std::string::npos) << s.name << " not in --help";
    std::vector<std::string> args = {"in.dba", s.name};
    if (s.kind != OptionKind::kFlag) args.push_back(GoodValue(s));
    // What needs a companion to be accepted.
    if (s.name == "--colmap-format") args.insert(args.end(), {"-o", "out"});
    if (s.name == "--checkpoint-every") args.insert(args.end(), {"--checkpoint", "c"});
    if (s.name == "--truth-absolute") args.insert(args.end(), {"--truth", "t"});
    if (s.name == "--gcp-crs") args.insert(args.end(), {"--gcps", "g"});
    if (s.name == "--output-crs" || s.name == "--accuracy-report") {
      args.insert(args.end(), {"--camera-priors", "p"});
    }
    if (s.name == "--rcs") args.insert(args.end(), {"--linear-solver", "pcg"});
    bool asked = false;
    EXPECT_NO_THROW(ParseSolveArguments(args, &asked)) << s.name << " " << GoodValue(s);
    EXPECT_EQ(s.modes & kModeCommandLine, kModeCommandLine) << s.name;
    if (!(s.modes & kModePythonArrays)) {
      EXPECT_FALSE(s.not_here.empty()) << s.name;
    }
  }
}

TEST(SolveOptionTable, ValuesOutsideTheirRangeAreRefusedNamingTheOption) {
  for (const OptionSpec<SolveOptions>& s : SolveOptionTable()) {
    std::vector<std::string> bad;
    if (s.kind == OptionKind::kInteger) bad = {std::to_string(static_cast<int64_t>(s.min) - 1), "1.5", "x"};
    if (s.kind == OptionKind::kNumber) bad = {"1e301", "nan", "inf", "-1e301", "x"};
    if (s.kind == OptionKind::kChoice) bad = {"none-of-them"};
    for (const std::string& v : bad) {
      bool asked = false;
      try {
        ParseSolveArguments({"in.dba", s.name, v}, &asked);
        ADD_FAILURE() << s.name << " " << v << " was accepted";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(s.name), std::string::npos) << e.what();
      }
    }
  }
  bool asked = false;
  EXPECT_THROW(ParseSolveArguments({"in.dba", "-t", "2", "--threads", "3"}, &asked),
               std::invalid_argument);
  EXPECT_NO_THROW(ParseSolveArguments(
      {"in.dba", "--fix-intrinsics", "f", "--fix-intrinsics", "0:k1"}, &asked));
}

TEST(SolveOptionTable, ReadmeHoldsTheTable) {
  std::ifstream in(std::string(DBA_REPO_DATA_DIR) + "/../README.md");
  std::stringstream readme;
  readme << in.rdbuf();
  const std::string table = OptionsMarkdown(SolveOptionTable(), SolveOptions());
  EXPECT_NE(readme.str().find(table), std::string::npos)
      << "README.md's option table is not the option table's: run "
         "scripts/update-option-table.sh";
}

}  // namespace
}  // namespace dba
