// The alignment onto the priors recovers a known similarity from noisy
// priors with 20% gross outliers, moves cameras and points consistently
// (every image sees the same), and says when the centres are collinear.
#include "dba/geo/prior_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "dba/camera/observation_residual.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

TEST(PriorAlignment, RecoversASimilarityThroughOutliers) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 30;
  o.geometry.num_points = 100;
  Problem problem = testing::MakeSyntheticPhoto(o).truth;
  // Priors: the centres moved by a known similarity, σ 0.02 noise, and 20%
  // of them 5 to 10 units off.
  const double s = 1.7;
  const Mat3 Q = AngleAxisToRotation(Vec3(0.4, -1.1, 2.0));
  const Vec3 T(120.0, -40.0, 15.0);
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 0.02);
  std::uniform_real_distribution<double> u(5.0, 10.0);
  CameraPriors priors;
  for (int32_t i = 0; i < problem.num_images(); ++i) {
    CameraCentrePrior p;
    p.image = i;
    p.centre = s * (Q * CameraCentre(problem.camera(i))) + T + Vec3(n(rng), n(rng), n(rng));
    if (i % 5 == 0) p.centre += u(rng) * Vec3(n(rng), n(rng), n(rng)).normalized();
    p.sigma = Vec3(0.02, 0.02, 0.04);
    priors.priors.push_back(p);
  }
  const SimilarityFit fit = AlignToPriors(priors, problem, Vec3::Zero());
  EXPECT_NEAR(fit.scale, s, 1e-3);
  EXPECT_LT((fit.rotation - Q).norm(), 1e-3);
  EXPECT_LT((fit.translation - T).norm(), 0.1);
  EXPECT_EQ(fit.inliers, 24);  // the 6 outliers left out
  EXPECT_FALSE(fit.collinear);

  // Applied: the centres land on the inlier priors, and the residuals of
  // every observation stay what they were.
  Problem moved = problem;
  ApplySimilarity(fit, &moved, &moved.points);
  for (const CameraCentrePrior& p : priors.priors) {
    if (p.image % 5 == 0) continue;
    EXPECT_LT((CameraCentre(moved.camera(p.image)) - p.centre).norm(), 0.1) << p.image;
  }
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    for (int64_t obs = problem.point_offsets[k]; obs < problem.point_offsets[k + 1]; ++obs) {
      const int32_t i = problem.obs_camera[obs];
      const Vec2 before = ObservationResidual(problem, problem.cameras.data(), i,
                                              problem.point(k), problem.pixel(obs));
      const Vec2 after = ObservationResidual(moved, moved.cameras.data(), i, moved.point(k),
                                             moved.pixel(obs));
      EXPECT_LT((after - before).norm(), 1e-6) << obs;
    }
  }
}

TEST(PriorAlignment, SaysWhenTheCentresAreCollinearAndRefusesTooFew) {
  CameraPriors priors;
  CameraSide side;
  side.model = CameraModel::kPhoto;
  std::vector<double>& cameras = side.cameras;
  for (int32_t i = 0; i < 6; ++i) {
    const double pose[6] = {0.0, 0.0, 0.0, -2.0 * i, 0.0, 0.0};  // centres on the x axis
    cameras.insert(cameras.end(), pose, pose + 6);
    CameraCentrePrior p;
    p.image = i;
    p.centre = Vec3(2.0 * i, 0.0, 0.0) + Vec3(5, 5, 5);
    priors.priors.push_back(p);
  }
  const SimilarityFit fit = AlignToPriors(priors, side, Vec3::Zero());
  EXPECT_TRUE(fit.collinear);
  EXPECT_NEAR(fit.scale, 1.0, 1e-9);
  priors.priors.resize(2);
  EXPECT_THROW(AlignToPriors(priors, side, Vec3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace dba
