// The UAV generator: deterministic bytes, consistent streaming binary and BAL
// outputs, sane geometry, and a generated problem solved back to the
// injected noise with the ground truth recovered.
#include "dba/synthetic/uav_generator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "dba/io/read_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/synthetic/ground_truth.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Tmp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

std::string Bytes(const std::string& path) { return testing::ReadFileBytes(path); }

UavSurveyOptions Small() {
  UavSurveyOptions o;
  o.images = 60;
  o.features_per_image = 150;
  o.physical_cameras = 2;
  o.seed = 7;
  return o;
}

TEST(UavGenerator, SameSeedSameBytesOtherSeedOtherBytes) {
  const UavSurveyOptions o = Small();
  GenerateUavSurvey(o, Tmp("a.dba"), Tmp("a.truth.dba"));
  GenerateUavSurvey(o, Tmp("b.dba"), Tmp("b.truth.dba"));
  EXPECT_EQ(Bytes(Tmp("a.dba")), Bytes(Tmp("b.dba")));
  EXPECT_EQ(Bytes(Tmp("a.truth.dba")), Bytes(Tmp("b.truth.dba")));
  UavSurveyOptions other = o;
  other.seed = 8;
  GenerateUavSurvey(other, Tmp("c.dba"), "");
  EXPECT_NE(Bytes(Tmp("a.dba")), Bytes(Tmp("c.dba")));
}

TEST(UavGenerator, BinaryAndBalTextHoldTheSameProblem) {
  const UavSurveyOptions o = Small();
  const UavSurveySummary s = GenerateUavSurvey(o, Tmp("p.dba"), Tmp("p.truth.dba"));
  GenerateUavSurvey(o, Tmp("p.txt"), Tmp("p.truth.txt"));
  const BalProblem bin = ReadProblem(Tmp("p.dba")), txt = ReadProblem(Tmp("p.txt"));
  EXPECT_EQ(bin.num_observations(), s.observations);
  EXPECT_EQ(bin.num_points(), s.points);
  EXPECT_EQ(bin.num_cameras(), o.images);
  EXPECT_EQ(bin.obs_camera, txt.obs_camera);
  EXPECT_EQ(bin.point_offsets, txt.point_offsets);
  EXPECT_EQ(bin.obs_pixel, txt.obs_pixel);  // shortest round-trip text is exact
  EXPECT_EQ(bin.cameras, txt.cameras);
  EXPECT_EQ(ReadProblem(Tmp("p.truth.dba")).obs_pixel, ReadProblem(Tmp("p.truth.txt")).obs_pixel);
}

TEST(UavGenerator, TracksFollowFromTheOverlap) {
  UavSurveyOptions o = Small();
  o.images = 200;
  const UavSurveySummary s = GenerateUavSurvey(o, Tmp("t.dba"), "");
  const double per_image = double(s.observations) / s.images;
  const double track = double(s.observations) / s.points;
  // About the requested features per image (edge images see fewer).
  EXPECT_GT(per_image, 0.5 * o.features_per_image);
  EXPECT_LT(per_image, 1.2 * o.features_per_image);
  // 80% forward and 60% side overlap: about 1/(0.2 * 0.4) = 12.5 images per
  // ground point inside the block, fewer at the edges.
  EXPECT_GT(track, 4.0);
  EXPECT_LT(track, 13.0);
  EXPECT_GT(s.strips, 1);
}

TEST(UavGenerator, SolvedToTheInjectedNoiseAndTheTruth) {
  UavSurveyOptions o = Small();
  o.pixel_noise = 1.0;
  GenerateUavSurvey(o, Tmp("s.dba"), Tmp("s.truth.dba"));
  BalProblem p = ReadProblem(Tmp("s.dba"));
  const BalProblem truth = ReadProblem(Tmp("s.truth.dba"));
  const GroundTruthErrors before = CompareWithGroundTruth(truth, p.cameras, p.points);
  LmOptions options;
  options.num_threads = 2;
  const LmSummary s = BundleAdjust(options, &p).lm;
  const GroundTruthErrors after = CompareWithGroundTruth(truth, p.cameras, p.points);
  // The streaming comparison from the file gives the same figures.
  const GroundTruthErrors streamed =
      CompareWithGroundTruthFile(Tmp("s.truth.dba"), p.cameras, p.points);
  EXPECT_NEAR(streamed.rms_to_noise_free_px, after.rms_to_noise_free_px,
              1e-12 * after.rms_to_noise_free_px);
  EXPECT_DOUBLE_EQ(streamed.camera_centre_rms, after.camera_centre_rms);
  // At the optimum the RMS (per observation, sqrt(2F/n)) is the noise's,
  // σ√2, less what the p parameters absorb: σ√2 · sqrt(1 - p / 2n).
  const double n = static_cast<double>(p.num_observations());
  const double params = 9.0 * p.num_cameras() + 3.0 * p.num_points();
  const double expected = std::sqrt(2.0) * o.pixel_noise * std::sqrt(1.0 - params / (2 * n));
  EXPECT_NEAR(s.Rms(s.final_cost), expected, 0.03 * expected);
  EXPECT_GT(s.Rms(s.initial_cost), 5.0);
  // Against the noise-free observations the solution is well inside the noise.
  EXPECT_LT(after.rms_to_noise_free_px, 0.6 * o.pixel_noise * std::sqrt(2.0));
  EXPECT_LT(after.rms_to_noise_free_px, 0.1 * before.rms_to_noise_free_px);
  // Points recovered up to a similarity. Camera centres stay about as far as
  // the 0.5 m start: with a focal length per image (the BAL model), nadir
  // images trade focal length for height (issue 6's shared intrinsics fix
  // that), so they are only bounded here.
  EXPECT_LT(after.point_rms, 0.7 * before.point_rms);
  EXPECT_LT(after.camera_centre_rms, 1.5);
  EXPECT_NEAR(after.similarity_scale, 1.0, 0.01);
}

TEST(UavGenerator, RefusesBadOptionsAndLeavesNoFile) {
  UavSurveyOptions o = Small();
  o.forward_overlap = 1.0;
  EXPECT_THROW(GenerateUavSurvey(o, Tmp("refused.dba"), ""), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(Tmp("refused.dba")));
}

}  // namespace
}  // namespace dba
