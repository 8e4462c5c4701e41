// The UAV generator: deterministic bytes, consistent streaming binary and BAL
// outputs, sane geometry, and a generated problem solved back to the
// injected noise with the ground truth recovered.
#include "dba/synthetic/uav_generator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "dba/camera/observation_residual.h"
#include "dba/io/read_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/synthetic/ground_truth.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Tmp(const std::string& name) { return dba::testing::TempPath(name); }

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
  const Problem bin = ReadProblem(Tmp("p.dba")), txt = ReadProblem(Tmp("p.txt"));
  EXPECT_EQ(bin.num_observations(), s.observations);
  EXPECT_EQ(bin.num_points(), s.points);
  EXPECT_EQ(bin.num_images(), o.images);
  EXPECT_EQ(bin.obs_camera, txt.obs_camera);
  EXPECT_EQ(bin.point_offsets, txt.point_offsets);
  EXPECT_EQ(bin.obs_pixel, txt.obs_pixel);  // shortest round-trip text is exact
  EXPECT_EQ(bin.cameras, txt.cameras);
  EXPECT_EQ(ReadProblem(Tmp("p.truth.dba")).obs_pixel, ReadProblem(Tmp("p.truth.txt")).obs_pixel);
}

// With the loaded pixels the generated mismatches leave the RMS to the
// noise-free pixels: at the true parameters it is then the noise alone, in
// memory and streamed from a .dba truth alike.
TEST(UavGenerator, MismatchesAreLeftOutOfTheRmsToTheTruth) {
  UavSurveyOptions o = Small();
  o.outlier_fraction = 0.05;
  GenerateUavSurvey(o, Tmp("m.dba"), Tmp("m.truth.dba"));
  const Problem p = ReadProblem(Tmp("m.dba")), truth = ReadProblem(Tmp("m.truth.dba"));
  int64_t mismatches = 0;
  for (int64_t a = 0; a < p.num_observations(); ++a) {
    mismatches += IsTrueOutlier(p.pixel(a), truth.pixel(a));
  }
  ASSERT_GT(mismatches, 0);
  const GroundTruthErrors all = CompareWithGroundTruth(truth, truth.cameras, truth.points);
  EXPECT_LT(all.rms_to_noise_free_px, 1e-9);  // the truth against itself
  // The solve's starting cameras against the truth: with and without the
  // mismatches' slots, in memory and streamed.
  const GroundTruthErrors with = CompareWithGroundTruth(truth, p.cameras, p.points);
  const GroundTruthErrors without =
      CompareWithGroundTruth(truth, p.cameras, p.points, CameraModel::kBal, {}, p.obs_pixel);
  const GroundTruthErrors streamed = CompareWithGroundTruthFile(
      Tmp("m.truth.dba"), p.cameras, p.points, CameraModel::kBal, {}, p.obs_pixel);
  EXPECT_EQ(with.rms_observations, p.num_observations());
  EXPECT_EQ(without.rms_observations, p.num_observations() - mismatches);
  EXPECT_EQ(without.mismatches_left_out, mismatches);
  EXPECT_EQ(streamed.mismatches_left_out, mismatches);
  EXPECT_NEAR(streamed.rms_to_noise_free_px, without.rms_to_noise_free_px,
              1e-12 * without.rms_to_noise_free_px);
  double sum = 0.0;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t a = p.point_offsets[k]; a < p.point_offsets[k + 1]; ++a) {
      if (IsTrueOutlier(p.pixel(a), truth.pixel(a))) continue;
      sum += ObservationResidual(truth, p.cameras.data(), p.obs_camera[a], p.point(k),
                                 truth.pixel(a)).squaredNorm();
    }
  }
  EXPECT_NEAR(without.rms_to_noise_free_px, std::sqrt(sum / (p.num_observations() - mismatches)),
              1e-12 * without.rms_to_noise_free_px);
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
  Problem p = ReadProblem(Tmp("s.dba"));
  const Problem truth = ReadProblem(Tmp("s.truth.dba"));
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
  // Per camera: the true centre and the error, whose RMS is the figure above.
  ASSERT_EQ(static_cast<int64_t>(after.centre_error.size()), p.num_images());
  ASSERT_EQ(after.centre_x.size(), after.centre_error.size());
  double squared = 0.0;
  for (double err : after.centre_error) squared += err * err;
  EXPECT_NEAR(std::sqrt(squared / p.num_images()), after.camera_centre_rms,
              1e-12 * after.camera_centre_rms);
  const Vec3 c0 = -AngleAxisToRotation(Vec3(truth.camera(0)[0], truth.camera(0)[1],
                                            truth.camera(0)[2])).transpose() *
                  Vec3(truth.camera(0)[3], truth.camera(0)[4], truth.camera(0)[5]);
  EXPECT_NEAR(after.centre_x[0], c0.x(), 1e-9);
  EXPECT_NEAR(after.centre_y[0], c0.y(), 1e-9);
  // At the optimum the RMS (per observation, sqrt(2F/n)) is the noise's,
  // σ√2, less what the p parameters absorb: σ√2 · sqrt(1 - p / 2n).
  const double n = static_cast<double>(p.num_observations());
  const double params = 9.0 * p.num_images() + 3.0 * p.num_points();
  const double expected = std::sqrt(2.0) * o.pixel_noise * std::sqrt(1.0 - params / (2 * n));
  EXPECT_NEAR(s.Rms(s.final_cost), expected, 0.03 * expected);
  EXPECT_GT(s.Rms(s.initial_cost), 5.0);
  // Against the noise-free observations the solution is well inside the noise.
  EXPECT_LT(after.rms_to_noise_free_px, 0.6 * o.pixel_noise * std::sqrt(2.0));
  EXPECT_LT(after.rms_to_noise_free_px, 0.1 * before.rms_to_noise_free_px);
  // Points and camera centres are only bounded here: with a focal length per
  // image (the BAL model), nadir images trade focal length for height, a
  // direction the cost hardly sees. The exact optimum (a factorized step)
  // moves along it: points 1.4 m from the truth against 0.6 m at the start,
  // where a truncated PCG step, which barely enters weak directions, stayed
  // near the start (0.4 m). Shared intrinsics fix it: the photogrammetric
  // test below checks the recovery.
  EXPECT_LT(after.point_rms, 3.0 * before.point_rms);
  EXPECT_LT(after.camera_centre_rms, 2.0);
  EXPECT_NEAR(after.similarity_scale, 1.0, 0.01);
}

UavSurveyOptions SmallPhoto() {
  UavSurveyOptions o = Small();
  o.model = CameraModel::kPhoto;
  return o;
}

TEST(UavGeneratorPhoto, SameSeedSameBytesOtherSeedOtherBytes) {
  const UavSurveyOptions o = SmallPhoto();
  GenerateUavSurvey(o, Tmp("pa.dba"), Tmp("pa.truth.dba"));
  GenerateUavSurvey(o, Tmp("pb.dba"), Tmp("pb.truth.dba"));
  EXPECT_EQ(Bytes(Tmp("pa.dba")), Bytes(Tmp("pb.dba")));
  EXPECT_EQ(Bytes(Tmp("pa.truth.dba")), Bytes(Tmp("pb.truth.dba")));
  UavSurveyOptions other = o;
  other.seed = 8;
  GenerateUavSurvey(other, Tmp("pc.dba"), "");
  EXPECT_NE(Bytes(Tmp("pa.dba")), Bytes(Tmp("pc.dba")));
  // Not the BAL file of the same survey.
  GenerateUavSurvey(Small(), Tmp("pd.dba"), "");
  EXPECT_NE(Bytes(Tmp("pa.dba")), Bytes(Tmp("pd.dba")));
}

TEST(UavGeneratorPhoto, OneSharedIntrinsicGroupPerPhysicalCamera) {
  const UavSurveyOptions o = SmallPhoto();
  const UavSurveySummary s = GenerateUavSurvey(o, Tmp("pg.dba"), Tmp("pg.truth.dba"));
  const Problem p = ReadProblem(Tmp("pg.dba")), truth = ReadProblem(Tmp("pg.truth.dba"));
  ASSERT_EQ(p.model, CameraModel::kPhoto);
  ASSERT_EQ(truth.model, CameraModel::kPhoto);
  EXPECT_EQ(p.num_images(), o.images);
  EXPECT_EQ(p.num_groups(), 2);
  EXPECT_EQ(s.intrinsic_groups, 2);
  EXPECT_EQ(p.num_observations(), s.observations);
  EXPECT_TRUE(p.fixed_cameras.empty());
  EXPECT_TRUE(p.fixed_intrinsics.empty());
  EXPECT_EQ(p.camera_intrinsics, truth.camera_intrinsics);
  EXPECT_EQ(p.obs_camera, truth.obs_camera);
  for (int64_t i = 0; i < p.num_images(); ++i) {
    EXPECT_EQ(p.camera_intrinsics[i], (i / s.images_per_strip) % 2) << i;
  }
  for (int g = 0; g < 2; ++g) {
    const double* t = truth.intrinsics(g);
    const double* q = p.intrinsics(g);
    EXPECT_NEAR(t[0], o.focal_px * (1.0 + 0.01 * g), 1e-9);
    // The principal point is near the image centre, not on it.
    EXPECT_NEAR(t[1], o.image_size / 2, 5.0);
    EXPECT_NEAR(t[2], o.image_size / 2, 5.0);
    EXPECT_NE(t[1], o.image_size / 2);
    // Only f starts perturbed (by about focal_perturbation).
    EXPECT_NE(q[0], t[0]);
    EXPECT_LT(std::abs(q[0] / t[0] - 1.0), 5 * o.focal_perturbation);
    for (int j = 1; j < 5; ++j) EXPECT_EQ(q[j], t[j]);
  }
  // The noise-free observations are the truth's projections, in the image
  // (origin at its corner).
  const GroundTruthErrors exact =
      CompareWithGroundTruth(truth, truth.cameras, truth.points, CameraModel::kPhoto);
  EXPECT_LT(exact.rms_to_noise_free_px, 1e-9);
  for (double v : truth.obs_pixel) {
    EXPECT_GE(v, 0.0);
    EXPECT_LT(v, o.image_size);
  }
  // More physical cameras than strips: only the ones flown are groups.
  UavSurveyOptions many = o;
  many.physical_cameras = 50;
  const UavSurveySummary m = GenerateUavSurvey(many, Tmp("pm.dba"), "");
  EXPECT_EQ(m.intrinsic_groups, m.strips);
  EXPECT_EQ(ReadProblem(Tmp("pm.dba")).num_groups(), m.strips);
}

TEST(UavGeneratorPhoto, SolvedRecoversTheIntrinsicsAndTheNoise) {
  // Big enough that f is well determined (about 0.2 % here for 1 px noise).
  UavSurveyOptions o = SmallPhoto();
  o.images = 100;
  o.features_per_image = 200;
  o.pixel_noise = 1.0;
  GenerateUavSurvey(o, Tmp("ps.dba"), Tmp("ps.truth.dba"));
  Problem p = ReadProblem(Tmp("ps.dba"));
  const Problem truth = ReadProblem(Tmp("ps.truth.dba"));
  const GroundTruthErrors before =
      CompareWithGroundTruth(truth, p.cameras, p.points, CameraModel::kPhoto);
  ASSERT_EQ(before.intrinsics_error.size(), 2u);
  LmOptions options;
  options.num_threads = 2;
  const LmSummary s = BundleAdjust(options, &p).lm;
  const GroundTruthErrors after =
      CompareWithGroundTruth(truth, p.cameras, p.points, CameraModel::kPhoto);
  const GroundTruthErrors streamed =
      CompareWithGroundTruthFile(Tmp("ps.truth.dba"), p.cameras, p.points, CameraModel::kPhoto);
  EXPECT_NEAR(streamed.rms_to_noise_free_px, after.rms_to_noise_free_px,
              1e-12 * after.rms_to_noise_free_px);
  EXPECT_DOUBLE_EQ(streamed.camera_centre_rms, after.camera_centre_rms);
  ASSERT_EQ(streamed.intrinsics_error.size(), 2u);
  EXPECT_EQ(streamed.intrinsics_error[1], after.intrinsics_error[1]);
  // RMS at the optimum: σ√2 · sqrt(1 - p / 2n) with p = 6 per image, 5 per
  // group, 3 per point.
  const double n = static_cast<double>(p.num_observations());
  const double params = 6.0 * p.num_images() + 5.0 * p.num_groups() + 3.0 * p.num_points();
  const double expected = std::sqrt(2.0) * o.pixel_noise * std::sqrt(1.0 - params / (2 * n));
  EXPECT_NEAR(s.Rms(s.final_cost), expected, 0.03 * expected);
  EXPECT_GT(s.Rms(s.initial_cost), 5.0);
  EXPECT_LT(after.rms_to_noise_free_px, 0.6 * o.pixel_noise * std::sqrt(2.0));
  // Intrinsics back within the noise: f within 0.5 %, the principal point
  // within a few pixels, the distortion within its small scale.
  for (size_t g = 0; g < 2; ++g) {
    const auto& e = after.intrinsics_error[g];
    EXPECT_LT(e[0] / after.true_focal[g], 0.005) << "group " << g;
    EXPECT_LT(e[1], 3.0) << "group " << g;
    EXPECT_LT(e[2], 3.0) << "group " << g;
    EXPECT_LT(e[3], 0.01) << "group " << g;
    EXPECT_LT(e[4], 0.01) << "group " << g;
  }
  // Shared intrinsics tie focal length and flying height: the centres and
  // points come back closer than they started.
  EXPECT_LT(after.camera_centre_rms, 0.7 * before.camera_centre_rms);
  EXPECT_LT(after.point_rms, 0.7 * before.point_rms);
  EXPECT_NEAR(after.similarity_scale, 1.0, 0.01);
  // A BAL solution is not compared with a photogrammetric truth.
  EXPECT_THROW(CompareWithGroundTruth(truth, p.cameras, p.points), std::invalid_argument);
  EXPECT_THROW(CompareWithGroundTruthFile(Tmp("ps.truth.dba"), p.cameras, p.points),
               std::invalid_argument);
}

TEST(UavGeneratorPhoto, TextOutputIsRefusedAndNothingWritten) {
  const std::string txt = Tmp("uav_photo.txt"), dba = Tmp("uav_photo.dba");
  std::filesystem::remove(txt);
  std::filesystem::remove(dba);
  EXPECT_THROW(GenerateUavSurvey(SmallPhoto(), txt, ""), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(txt));
  EXPECT_THROW(GenerateUavSurvey(SmallPhoto(), dba, Tmp("uav_photo.truth.txt")),
               std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dba));
}

TEST(UavGenerator, RefusesBadOptionsAndLeavesNoFile) {
  UavSurveyOptions o = Small();
  o.forward_overlap = 1.0;
  EXPECT_THROW(GenerateUavSurvey(o, Tmp("refused.dba"), ""), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(Tmp("refused.dba")));
}

}  // namespace
}  // namespace dba
