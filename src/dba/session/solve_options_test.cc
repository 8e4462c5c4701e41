// `dba solve`'s argument parser: every refusal names the flag and what it did
// not accept (a table of cases), and the accepted options land in the options.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dba/session/solve_options.h"

namespace dba {
namespace {

struct Refusal {
  const char* name;
  std::vector<std::string> args;
  const char* message;  // a part of the error message
};
void PrintTo(const Refusal& r, std::ostream* out) { *out << r.name; }

class SolveArgumentRefusals : public ::testing::TestWithParam<Refusal> {};

TEST_P(SolveArgumentRefusals, NamesTheFlagAndTheValue) {
  const Refusal& r = GetParam();
  bool help = false;
  try {
    ParseSolveArguments(r.args, &help);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(r.message), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, SolveArgumentRefusals,
    ::testing::Values(
        Refusal{"no_input", {}, "missing INPUT"},
        Refusal{"two_inputs", {"a.txt", "b.txt"}, "more than one input file: 'a.txt' and 'b.txt'"},
        Refusal{"unknown_option", {"a.txt", "--bogus"}, "unknown option '--bogus'"},
        Refusal{"missing_value", {"a.txt", "-o"}, "-o: missing value"},
        Refusal{"threads_zero", {"a.txt", "-t", "0"}, "-t"},
        Refusal{"threads_too_many", {"a.txt", "-t", "100000"}, "[1, 1024]"},
        Refusal{"threads_not_a_number", {"a.txt", "--threads", "two"}, "--threads"},
        Refusal{"bad_main_rank", {"a.txt", "--main-rank", "boss"}, "--main-rank: expected auto, forms or coordinates, got 'boss'"},
        Refusal{"bad_intrinsics", {"a.txt", "--intrinsics", "some"}, "--intrinsics: expected shared or per-image, got 'some'"},
        Refusal{"bad_colmap_format", {"a.txt", "-o", "d", "--colmap-format", "json"}, "--colmap-format: expected text or binary, got 'json'"},
        Refusal{"colmap_format_without_output", {"a.txt", "--colmap-format", "text"}, "--colmap-format: no -o output"},
        Refusal{"bad_linear_solver", {"a.txt", "--linear-solver", "qr"}, "--linear-solver: expected auto, dense, sparse or pcg, got 'qr'"},
        Refusal{"bad_preconditioner", {"a.txt", "--preconditioner", "ilu"}, "--preconditioner: expected jacobi or two-level, got 'ilu'"},
        Refusal{"bad_coarse_basis", {"a.txt", "--coarse-basis", "affine"}, "--coarse-basis: expected similarity, rigid or parameters, got 'affine'"},
        Refusal{"negative_eta", {"a.txt", "--eta", "-1"}, "--eta"},
        Refusal{"bad_pcg_precision", {"a.txt", "--pcg-precision", "half"}, "--pcg-precision: expected auto, mixed or double, got 'half'"},
        Refusal{"bad_loss", {"a.txt", "--loss", "l1"}, "--loss: expected trivial, huber, soft_l1, cauchy, arctan or tukey, got 'l1'"},
        Refusal{"zero_loss_scale", {"a.txt", "--loss-scale", "0"}, "--loss-scale: expected a number in [1e-06, 10000], got '0'"},
        Refusal{"zero_reject_outliers", {"a.txt", "--reject-outliers", "0"}, "--reject-outliers: expected a number in [1e-06, 1e+06], got '0'"},
        Refusal{"negative_triangulation_angle", {"a.txt", "--min-triangulation-angle", "-1"}, "--min-triangulation-angle: expected a number in [0, 179.9]"},
        Refusal{"straight_triangulation_angle", {"a.txt", "--min-triangulation-angle", "180"}, "--min-triangulation-angle: expected a number in [0, 179.9]"},
        Refusal{"bad_partition", {"a.txt", "--partition", "random"}, "--partition: expected equal or cameras, got 'random'"},
        Refusal{"bad_rcs", {"a.txt", "--rcs", "scatter"}, "--rcs: expected auto, gather or distributed, got 'scatter'"},
        Refusal{"distributed_rcs_with_sparse", {"a.txt", "--rcs", "distributed", "--linear-solver", "sparse"}, "--rcs distributed solves by PCG; --linear-solver sparse needs --rcs gather"},
        Refusal{"bad_fix_intrinsics_group", {"a.txt", "--fix-intrinsics", "1,2:f"}, "--fix-intrinsics: one group before ':'"},
        Refusal{"empty_fix_intrinsics", {"a.txt", "--fix-intrinsics", "0:"}, "--fix-intrinsics: empty list"},
        Refusal{"bad_max_iterations", {"a.txt", "--max-iterations", "-3"}, "--max-iterations"},
        Refusal{"nan_tolerance", {"a.txt", "--function-tolerance", "nan"}, "--function-tolerance"}),
    [](const ::testing::TestParamInfo<Refusal>& info) { return std::string(info.param.name); });

TEST(SolveArguments, AcceptedOptionsLandInTheOptions) {
  bool help = false;
  const SolveOptions o = ParseSolveArguments(
      {"in.dba", "-o", "out.dba", "--report", "r.json", "-t", "3", "--linear-solver", "sparse",
       "--loss", "huber", "--loss-scale", "2.5", "--reject-outliers", "4", "--reject-keep-loss", "--eta", "0.2",
       "--coarse-basis", "parameters", "--pcg-precision", "double", "--min-triangulation-angle", "2", "-q"},
      &help);
  EXPECT_FALSE(help);
  EXPECT_EQ(o.input, "in.dba");
  EXPECT_EQ(o.output, "out.dba");
  EXPECT_EQ(o.report_path, "r.json");
  EXPECT_EQ(o.lm.num_threads, 3);
  EXPECT_EQ(o.lm.linear_solver.type, LinearSolverType::kSparse);
  EXPECT_EQ(o.lm.loss.type, LossType::kHuber);
  EXPECT_EQ(o.lm.loss.scale, 2.5);
  EXPECT_EQ(o.reject_outliers_px, 4.0);
  EXPECT_TRUE(o.reject_keep_loss);
  EXPECT_EQ(o.min_triangulation_angle_deg, 2.0);
  EXPECT_EQ(o.lm.linear_solver.pcg.eta, 0.2);
  EXPECT_EQ(o.lm.linear_solver.coarse_basis, CoarseBasis::kParameters);
  EXPECT_EQ(o.lm.linear_solver.pcg.precision, PcgPrecision::kDouble);
  EXPECT_TRUE(o.quiet);
  ParseSolveArguments({"--help"}, &help);
  EXPECT_TRUE(help);
}

// --reject-outliers without --loss starts robust: Cauchy at 2 PX (its scale
// --loss-scale's when given); a --loss given, even the squared one, stays;
// without rejection the default loss is the squared one.
TEST(SolveArguments, RejectionWithoutALossStartsWithCauchyAtTwiceTheThreshold) {
  bool help = false;
  auto loss = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "in.dba");
    return ParseSolveArguments(args, &help).lm.loss;
  };
  const RobustLoss start = loss({"--reject-outliers", "3"});
  EXPECT_EQ(start.type, LossType::kCauchy);
  EXPECT_EQ(start.scale, 6.0);
  EXPECT_EQ(loss({"--reject-outliers", "3", "--loss-scale", "4"}).scale, 4.0);
  EXPECT_EQ(loss({"--reject-outliers", "3", "--loss", "trivial"}).type, LossType::kTrivial);
  const RobustLoss huber = loss({"--loss", "huber", "--loss-scale", "2", "--reject-outliers", "3"});
  EXPECT_EQ(huber.type, LossType::kHuber);
  EXPECT_EQ(huber.scale, 2.0);
  EXPECT_EQ(loss({}).type, LossType::kTrivial);
  EXPECT_EQ(ParseSolveArguments({"in.dba"}, &help).reject_max_share, 0.25);
  EXPECT_EQ(ParseSolveArguments({"in.dba", "--reject-max-share", "0.5"}, &help).reject_max_share, 0.5);
}

}  // namespace
}  // namespace dba
