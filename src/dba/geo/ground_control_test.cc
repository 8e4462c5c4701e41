// Ground control in a solve: check points triangulated from known cameras
// in both camera models, the block aligned onto control points through a
// known similarity, and control points added and taken out again.
#include "dba/geo/ground_control.h"

#include <gtest/gtest.h>

#include <random>

#include "dba/camera/observation_residual.h"
#include "dba/camera/rotation.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

// Points 3, 17, 29 and 41 of the truth as surveyed points, measured where
// the truth sees them with `sigma_px` of noise.
GroundControl FromTruth(const Problem& truth, bool control, double sigma_px = 0.5) {
  EXPECT_GT(truth.num_points(), 41);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma_px);
  GroundControl g;
  for (int64_t k : {3, 17, 29, 41}) {
    GroundControlPoint p;
    p.name = "P" + std::to_string(k);
    p.position = Vec3(truth.point(k));
    p.sigma = Vec3(0.01, 0.01, 0.02);
    p.control = control;
    for (int64_t o = truth.point_offsets[k]; o < truth.point_offsets[k + 1]; ++o) {
      p.measurements.push_back({truth.obs_camera[o], Vec2(truth.pixel(o)) + Vec2(noise(rng), noise(rng))});
    }
    g.points.push_back(p);
  }
  return g;
}

class TriangulationTest : public ::testing::TestWithParam<bool> {};

TEST_P(TriangulationTest, CheckPointsLandOnTheirTruthFromTheTiePoints) {
  testing::SyntheticProblem s;
  if (GetParam()) {
    testing::SyntheticPhotoOptions o;
    o.geometry.num_cameras = 8;
    o.geometry.num_points = 60;
    o.lens_model = LensModel::kOpenCV;
    s = testing::MakeSyntheticPhoto(o);
  } else {
    testing::SyntheticBalOptions o;
    o.num_cameras = 8;
    o.num_points = 60;
    s = testing::MakeSyntheticBal(o);
  }
  const GroundControl g = FromTruth(s.truth, false);
  // The truth's cameras with the problem's (perturbed) points as tie points:
  // the starts are off, the cameras exact.
  Problem cameras_true = s.problem;
  cameras_true.cameras = s.truth.cameras;
  const std::vector<Triangulation> t = TriangulateGroundControl(cameras_true, g, false, false);
  ASSERT_EQ(t.size(), 4u);
  for (size_t x = 0; x < t.size(); ++x) {
    ASSERT_TRUE(t[x].ok);
    EXPECT_LT(t[x].rms_px, 1.5);
    const double scale = 1.0 + g.points[x].position.norm();
    EXPECT_LT((t[x].X - g.points[x].position).norm(), 0.02 * scale) << g.points[x].name;
  }
  // No observations to start from: the surveyed position is the start.
  Problem bare = cameras_true;
  bare.point_offsets.clear();
  const std::vector<Triangulation> u = TriangulateGroundControl(bare, g, false, true);
  for (size_t x = 0; x < u.size(); ++x) EXPECT_LT((u[x].X - t[x].X).norm(), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Models, TriangulationTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "photo_opencv" : "bal"; });

TEST(GroundControl, AlignmentRecoversTheSimilarityOfTheControlPoints) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 8;
  o.num_points = 60;
  const testing::SyntheticProblem s = testing::MakeSyntheticBal(o);
  GroundControl g = FromTruth(s.truth, true, 0.0);
  // The surveyed frame: the truth moved by a known similarity.
  Similarity known;
  known.scale = 2.5;
  known.rotation = AngleAxisToRotation(Vec3(0.3, -0.2, 1.1));
  known.translation = Vec3(100, -50, 20);
  for (GroundControlPoint& p : g.points) p.position = known.Apply(p.position);
  const SimilarityFit fit = AlignToControlPoints(g, TriangulateGroundControl(s.truth, g, true, false));
  EXPECT_NEAR(fit.scale, known.scale, 1e-6);
  EXPECT_LT((fit.rotation - known.rotation).norm(), 1e-6);
  EXPECT_LT((fit.translation - known.translation).norm(), 1e-4);
  g.points.resize(2);
  EXPECT_THROW(AlignToControlPoints(g, TriangulateGroundControl(s.truth, g, true, false)),
               std::invalid_argument);
}

TEST(GroundControl, ControlPointsAreAppendedWithTheirPriorsAndTakenOutAgain) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 6;
  o.num_points = 60;
  const testing::SyntheticProblem s = testing::MakeSyntheticBal(o);
  Problem p = s.problem;
  const Problem before = p;
  GroundControl g = FromTruth(s.truth, true);
  g.points[1].control = false;  // a check point is not added
  AddControlPoints(g, &p);
  ASSERT_EQ(p.num_points(), before.num_points() + 3);
  ASSERT_EQ(p.point_priors.size(), 3u);
  const PointPrior* prior = p.point_prior(before.num_points() + 1);
  ASSERT_NE(prior, nullptr);
  EXPECT_EQ(prior->position[2], g.points[2].position.z());
  EXPECT_EQ(prior->weight[2], 1.0 / 0.02);
  EXPECT_EQ(p.point_offsets.back() - p.point_offsets[before.num_points() + 2],
            static_cast<int64_t>(g.points[3].measurements.size()));
  p.points[3 * before.num_points()] += 1.0;  // "adjusted"
  const std::vector<double> adjusted = RemoveControlPoints(3, &p);
  EXPECT_EQ(adjusted[0], g.points[0].position.x() + 1.0);
  EXPECT_EQ(p.points, before.points);
  EXPECT_EQ(p.point_offsets, before.point_offsets);
  EXPECT_EQ(p.obs_camera, before.obs_camera);
  EXPECT_EQ(p.obs_pixel, before.obs_pixel);
  EXPECT_TRUE(p.point_priors.empty());
}

}  // namespace
}  // namespace dba
