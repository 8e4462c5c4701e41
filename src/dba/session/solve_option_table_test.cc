// One declaration of `dba solve`'s options: every option of the table is in
// --help, is accepted by the parser with a value of its kind and refused
// outside its range, and README.md's table is the one the table makes.
#include "dba/session/solve_option_table.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
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

// What gives an option what it needs (OptionSpec::needs); nothing where
// the defaults do (--linear-solver auto, --preconditioner two-level).
std::vector<std::string> Companions(const OptionSpec<SolveOptions>& s) {
  const std::map<std::string, std::vector<std::string>> by_needs = {
      {"", {}},
      {"-o", {"-o", "out"}},
      {"--checkpoint", {"--checkpoint", "c"}},
      {"--truth", {"--truth", "t"}},
      {"--camera-priors", {"--camera-priors", "p"}},
      {"--camera-priors or --gcps", {"--gcps", "g"}},
      {"--gcps", {"--gcps", "g"}},
      {"--prior-crs or --gcp-crs", {"--camera-priors", "p", "--prior-crs", "EPSG:4979"}},
      {"--reject-outliers", {"--reject-outliers", "3"}},
      {"--covariance", {"--covariance", "c.csv"}},
      {"--ply", {"--ply", "x.ply"}},
      {"--linear-solver pcg or auto", {}},
      {"--preconditioner two-level, with --linear-solver pcg or auto", {}},
  };
  const auto c = by_needs.find(s.needs);
  if (c == by_needs.end()) ADD_FAILURE() << s.name << " needs '" << s.needs << "': add its companion";
  return c == by_needs.end() ? std::vector<std::string>{} : c->second;
}

TEST(SolveOptionTable, EveryOptionIsInTheHelpAndParses) {
  std::ostringstream help;
  PrintSolveHelp(help);
  for (const OptionSpec<SolveOptions>& s : SolveOptionTable()) {
    EXPECT_NE(help.str().find(s.name), std::string::npos) << s.name << " not in --help";
    std::vector<std::string> args = {"in.dba", s.name};
    if (s.kind != OptionKind::kFlag) args.push_back(GoodValue(s));
    bool asked = false;
    const std::vector<std::string> companions = Companions(s);
    if (!companions.empty()) {  // alone, refused naming what it needs
      try {
        ParseSolveArguments(args, &asked);
        ADD_FAILURE() << s.name << " accepted without " << s.needs;
      } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), s.name + " needs " + s.needs);
      }
    }
    args.insert(args.end(), companions.begin(), companions.end());
    if (s.name == "--rcs") args.insert(args.end(), {"--linear-solver", "pcg"});
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
