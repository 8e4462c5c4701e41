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
        Refusal{"colmap_format_without_output", {"a.txt", "--colmap-format", "text"}, "--colmap-format needs -o"},
        Refusal{"bad_linear_solver", {"a.txt", "--linear-solver", "qr"}, "--linear-solver: expected auto, dense, sparse or pcg, got 'qr'"},
        Refusal{"bad_preconditioner", {"a.txt", "--preconditioner", "ilu"}, "--preconditioner: expected jacobi or two-level, got 'ilu'"},
        Refusal{"bad_coarse_basis", {"a.txt", "--coarse-basis", "affine"}, "--coarse-basis: expected similarity, rigid or parameters, got 'affine'"},
        Refusal{"negative_eta", {"a.txt", "--eta", "-1"}, "--eta"},
        Refusal{"bad_pcg_precision", {"a.txt", "--pcg-precision", "half"}, "--pcg-precision: expected auto, mixed or double, got 'half'"},
        Refusal{"bad_loss", {"a.txt", "--loss", "l1"}, "--loss: expected trivial, huber, soft_l1, cauchy, arctan or tukey, got 'l1'"},
        Refusal{"zero_loss_scale", {"a.txt", "--loss-scale", "0"}, "--loss-scale: expected a number in [0.01, 10000], got '0'"},
        Refusal{"denormal_initial_lambda", {"a.txt", "--initial-lambda", "1e-320"}, "--initial-lambda: expected a number in [1e-16, 10000], got '1e-320'"},
        Refusal{"huge_initial_lambda", {"a.txt", "--initial-lambda", "2147483648"}, "--initial-lambda: expected a number in [1e-16, 10000], got '2147483648'"},
        Refusal{"microscopic_loss_scale", {"a.txt", "--loss", "tukey", "--loss-scale", "1e-6"}, "--loss-scale: expected a number in [0.01, 10000], got '1e-6'"},
        Refusal{"zero_reject_outliers", {"a.txt", "--reject-outliers", "0"}, "--reject-outliers: expected a number in [1e-06, 1e+06], got '0'"},
        Refusal{"negative_triangulation_angle", {"a.txt", "--min-triangulation-angle", "-1"}, "--min-triangulation-angle: expected a number in [0, 179.9]"},
        Refusal{"straight_triangulation_angle", {"a.txt", "--min-triangulation-angle", "180"}, "--min-triangulation-angle: expected a number in [0, 179.9]"},
        Refusal{"bad_partition", {"a.txt", "--partition", "random"}, "--partition: expected equal or cameras, got 'random'"},
        Refusal{"bad_rcs", {"a.txt", "--rcs", "scatter"}, "--rcs: expected auto, gather or distributed, got 'scatter'"},
        Refusal{"distributed_rcs_with_sparse", {"a.txt", "--rcs", "distributed", "--linear-solver", "sparse"}, "--rcs distributed solves by PCG; --linear-solver sparse needs --rcs gather"},
        Refusal{"bad_fix_intrinsics_group", {"a.txt", "--fix-intrinsics", "1,2:f"}, "--fix-intrinsics: one group before ':'"},
        Refusal{"empty_fix_intrinsics", {"a.txt", "--fix-intrinsics", "0:"}, "--fix-intrinsics: empty list"},
        Refusal{"bad_max_iterations", {"a.txt", "--max-iterations", "-3"}, "--max-iterations"},
        Refusal{"nan_tolerance", {"a.txt", "--function-tolerance", "nan"}, "--function-tolerance"},
        // Options that mean nothing without another (OptionSpec::needs).
        Refusal{"prior_crs_alone", {"a.txt", "--prior-crs", "EPSG:4979"}, "--prior-crs needs --camera-priors or --gcps"},
        Refusal{"prior_sigma_with_gcps", {"a.txt", "--gcps", "g.txt", "--prior-sigma", "1,2"}, "--prior-sigma needs --camera-priors"},
        Refusal{"prior_loss_alone", {"a.txt", "--prior-loss", "huber"}, "--prior-loss needs --camera-priors"},
        Refusal{"prior_loss_scale_alone", {"a.txt", "--prior-loss-scale", "2"}, "--prior-loss-scale needs --camera-priors"},
        Refusal{"lever_arm_with_gcps", {"a.txt", "--lever-arm", "0,0,1", "--gcps", "g.txt"}, "--lever-arm needs --camera-priors"},
        Refusal{"refine_lever_arm_alone", {"a.txt", "--refine-lever-arm"}, "--refine-lever-arm needs --camera-priors"},
        Refusal{"gcp_crs_with_priors", {"a.txt", "--camera-priors", "p.txt", "--gcp-crs", "EPSG:4979"}, "--gcp-crs needs --gcps"},
        Refusal{"output_crs_without_a_crs", {"a.txt", "--camera-priors", "p.txt", "--output-crs", "EPSG:4979"}, "--output-crs needs --prior-crs or --gcp-crs"},
        Refusal{"accuracy_report_alone", {"a.txt", "--accuracy-report", "r.txt"}, "--accuracy-report needs --camera-priors or --gcps"},
        Refusal{"reject_keep_loss_alone", {"a.txt", "--loss", "huber", "--reject-keep-loss"}, "--reject-keep-loss needs --reject-outliers"},
        Refusal{"triangulation_angle_alone", {"a.txt", "--min-triangulation-angle", "2"}, "--min-triangulation-angle needs --reject-outliers"},
        Refusal{"checkpoint_every_alone", {"a.txt", "--checkpoint-every", "0"}, "--checkpoint-every needs --checkpoint"},
        Refusal{"truth_absolute_alone", {"a.txt", "--truth-absolute"}, "--truth-absolute needs --truth"},
        Refusal{"colmap_version_without_output", {"a.txt", "--colmap-version", "3.8"}, "--colmap-version needs -o"},
        Refusal{"eta_with_dense", {"a.txt", "--linear-solver", "dense", "--eta", "0.2"}, "--eta needs --linear-solver pcg or auto"},
        Refusal{"pcg_precision_with_sparse", {"a.txt", "--pcg-precision", "double", "--linear-solver", "sparse"}, "--pcg-precision needs --linear-solver pcg or auto"},
        Refusal{"coarse_size_with_jacobi", {"a.txt", "--preconditioner", "jacobi", "--coarse-size", "8"}, "--coarse-size needs --preconditioner two-level, with --linear-solver pcg or auto"}),
    [](const ::testing::TestParamInfo<Refusal>& info) { return std::string(info.param.name); });

TEST(SolveArguments, AcceptedOptionsLandInTheOptions) {
  bool help = false;
  const SolveOptions o = ParseSolveArguments(
      {"in.dba", "-o", "out.dba", "--report", "r.json", "-t", "3", "--linear-solver", "pcg",
       "--loss", "huber", "--loss-scale", "2.5", "--reject-outliers", "4", "--reject-keep-loss", "--eta", "0.2",
       "--coarse-basis", "parameters", "--pcg-precision", "double", "--min-triangulation-angle", "2", "-q"},
      &help);
  EXPECT_FALSE(help);
  EXPECT_EQ(o.input, "in.dba");
  EXPECT_EQ(o.output, "out.dba");
  EXPECT_EQ(o.report_path, "r.json");
  EXPECT_EQ(o.lm.num_threads, 3);
  EXPECT_EQ(o.lm.linear_solver.type, LinearSolverType::kPcg);
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

// What an option needs may come before or after it, and a default that has
// it counts (auto may solve by PCG; two-level is the default preconditioner).
TEST(SolveArguments, OptionsWithWhatTheyNeedAreAccepted) {
  bool help = false;
  const SolveOptions o = ParseSolveArguments(
      {"in.dba", "--prior-crs", "EPSG:4979", "--gcps", "g.txt", "--output-crs", "EPSG:4978",
       "--min-triangulation-angle", "3", "--reject-outliers", "4", "--coarse-size", "5", "--eta",
       "0.3", "--gcp-crs", "EPSG:4326", "--checkpoint-every", "2", "--checkpoint", "c.ckpt"},
      &help);
  EXPECT_EQ(o.geo.prior_crs, "EPSG:4979");
  EXPECT_EQ(o.min_triangulation_angle_deg, 3.0);
  EXPECT_EQ(o.lm.linear_solver.coarse_aggregate_size, 5);
  EXPECT_EQ(o.checkpoint_every_s, 2.0);
  // "--" ends the options: an input whose name starts with '-'.
  EXPECT_EQ(ParseSolveArguments({"-q", "--", "-in.dba"}, &help).input, "-in.dba");
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
  EXPECT_EQ(ParseSolveArguments({"in.dba", "--reject-outliers", "3", "--reject-max-share", "0.5"}, &help)
                .reject_max_share,
            0.5);
}

}  // namespace
}  // namespace dba
