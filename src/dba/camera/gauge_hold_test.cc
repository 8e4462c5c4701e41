// The held gauge against hand-built similarities: a model moved by one
// (and disturbed) is mapped back so that its centres' centroid, RMS
// spread and mean orientation, a fixed image's pose, or COLMAP's first
// pose and second x translation are as loaded; an unmoved model maps by
// the identity exactly.
#include "dba/camera/gauge_hold.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

namespace dba {
namespace {

// n images of one intrinsic group, poses at random about a scene 20 across.
CameraSide RandomSide(int n, unsigned seed) {
  CameraSide side;
  side.model = CameraModel::kPhoto;
  side.camera_intrinsics.assign(n, 0);
  side.cameras.assign(kPhotoPoseSize * n + side.intrinsics_size, 0.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i) {
    double* p = side.camera(i);
    for (int k = 0; k < 3; ++k) p[k] = 1.5 * u(rng), p[3 + k] = 10.0 * u(rng);
  }
  return side;
}

// The world moved by `s`, then each pose disturbed by up to `noise`.
CameraSide Moved(const CameraSide& in, const Similarity& s, double noise, unsigned seed = 7) {
  CameraSide out = in;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  for (int64_t i = 0; i < out.num_images(); ++i) {
    if (out.camera_fixed(i)) continue;
    MovePose(s, out.camera(i));
    for (int k = 0; k < 6; ++k) out.camera(i)[k] += u(rng);
  }
  return out;
}

const Similarity kWorld{1.7, AngleAxisToRotation(Vec3(0.3, -0.2, 0.5)), Vec3(4.0, -2.0, 7.0)};

double Angle(const Mat3& R) { return Eigen::AngleAxisd(R).angle(); }

void ExpectSameMean(const PoseSetMean& a, const PoseSetMean& b, double tolerance) {
  EXPECT_LT((a.centroid - b.centroid).norm(), tolerance * b.spread);
  EXPECT_NEAR(a.spread / b.spread, 1.0, tolerance);
  EXPECT_LT(Angle(a.orientation.transpose() * b.orientation), tolerance);
}

PoseSetMean MeanOf(const CameraSide& side) {
  return MeanOfPoses(side.cameras.data(), side.num_images(), side.camera_size());
}

TEST(PoseSetMean, CentroidSpreadAndChordalMeanByHand) {
  // Two centres (0,0,0) and (2,0,0): centroid (1,0,0), spread 1. Rotations
  // ±0.4 rad about z from R0: their chordal mean is R0.
  const Mat3 R0 = AngleAxisToRotation(Vec3(0.2, 0.1, -0.3));
  double poses[12];
  for (int i = 0; i < 2; ++i) {
    const Mat3 R = AngleAxisToRotation(Vec3(0, 0, i == 0 ? 0.4 : -0.4)) * R0;
    const Eigen::AngleAxisd aa(R);
    const Vec3 w = aa.angle() * aa.axis(), t = -R * Vec3(2.0 * i, 0, 0);
    for (int k = 0; k < 3; ++k) poses[6 * i + k] = w[k], poses[6 * i + 3 + k] = t[k];
  }
  const PoseSetMean m = MeanOfPoses(poses, 2, 6);
  EXPECT_LT((m.centroid - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_NEAR(m.spread, 1.0, 1e-15);
  EXPECT_LT(Angle(m.orientation.transpose() * R0), 1e-14);
  // A rotation is its own nearest; a reflection's nearest has det +1.
  EXPECT_LT((NearestRotation(R0) - R0).norm(), 1e-15);
  EXPECT_NEAR(NearestRotation(-R0).determinant(), 1.0, 1e-14);
}

TEST(GaugeHold, MeanMapsAHandBuiltSimilarityBack) {
  const CameraSide in = RandomSide(9, 1);
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kHold);
  ASSERT_EQ(ref.hold, GaugeHold::kMean);
  CameraSide solved = Moved(in, kWorld, 0.0);
  const Similarity back = GaugeMapping(ref, solved);
  // The inverse of X' = s Q X + T: X = (1/s) Qᵀ X' − (1/s) Qᵀ T.
  EXPECT_NEAR(back.scale, 1 / kWorld.scale, 1e-14);
  EXPECT_LT(Angle(back.rotation * kWorld.rotation), 1e-14);
  EXPECT_LT((back.translation + kWorld.rotation.transpose() * kWorld.translation / kWorld.scale).norm(),
            1e-13);
  MoveCameras(back, &solved);
  for (int64_t i = 0; i < in.num_images(); ++i) {
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(solved.camera(i)[k], in.camera(i)[k], 1e-12);
  }
  ExpectSameMean(MeanOf(solved), ref.mean, 1e-14);
  EXPECT_EQ(DescribeGauge(ref, back),
            "the centres' centroid, RMS spread and mean orientation (the optimum mapped back: scale "
            "0.588235294, rotation 0.616 rad)");
}

TEST(GaugeHold, MeanIsHeldWhenTheSolveAlsoMovedTheImagesApart) {
  const CameraSide in = RandomSide(12, 2);
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kHold);
  CameraSide solved = Moved(in, kWorld, 0.05);
  MoveCameras(GaugeMapping(ref, solved), &solved);
  ExpectSameMean(MeanOf(solved), ref.mean, 1e-14);
  // Without the mapping it is not (the test can fail).
  EXPECT_GT(std::abs(MeanOf(Moved(in, kWorld, 0.05)).spread / ref.mean.spread - 1), 0.5);
}

TEST(GaugeHold, AnUnmovedModelMapsByTheIdentityExactly) {
  CameraSide in = RandomSide(7, 3);
  for (GaugeRule rule : {GaugeRule::kHold, GaugeRule::kColmap}) {
    const Similarity s = GaugeMapping(TakeGaugeReference(in, rule), in);
    EXPECT_EQ(s.scale, 1.0);
    EXPECT_TRUE(s.rotation == Mat3::Identity());
    EXPECT_TRUE(s.translation == Vec3::Zero());
  }
  in.fixed_cameras.assign(7, 0);
  in.fixed_cameras[4] = 1;
  const Similarity s = GaugeMapping(TakeGaugeReference(in, GaugeRule::kHold), in);
  EXPECT_TRUE(s.scale == 1.0 && s.rotation == Mat3::Identity() && s.translation.isZero(0));
}

TEST(GaugeHold, OneFixedImageKeepsTheSpreadByScalingAboutItsCentre) {
  CameraSide in = RandomSide(8, 4);
  in.fixed_cameras.assign(8, 0);
  in.fixed_cameras[2] = 1;
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kHold);
  ASSERT_EQ(ref.hold, GaugeHold::kFixedImage);
  EXPECT_EQ(ref.anchor, 2);
  const Vec3 C = CameraCentre(in.camera(2));
  CameraSide solved = Moved(in, Similarity{1.3, Mat3::Identity(), -0.3 * C}, 0.0);
  const Similarity back = GaugeMapping(ref, solved);
  EXPECT_NEAR(back.scale, 1 / 1.3, 1e-14);
  EXPECT_TRUE(back.rotation == Mat3::Identity());
  EXPECT_LT((back.translation - (1 - 1 / 1.3) * C).norm(), 1e-13);
  MoveCameras(back, &solved);
  EXPECT_NEAR(MeanOf(solved).spread / ref.mean.spread, 1.0, 1e-14);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(solved.camera(2)[k], in.camera(2)[k]);
  EXPECT_EQ(DescribeGauge(ref, back, std::vector<int64_t>{5, 6, 17, 20, 21, 22, 23, 24}).substr(0, 50),
            "fixed image 17, and the centres' RMS spread (the o");
}

TEST(GaugeHold, TwoFixedImagesHoldEverything) {
  CameraSide in = RandomSide(6, 5);
  in.fixed_cameras = {0, 1, 0, 0, 1, 0};
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kColmap);
  EXPECT_EQ(ref.hold, GaugeHold::kFixedImages);
  const Similarity s = GaugeMapping(ref, Moved(in, kWorld, 0.0));
  EXPECT_TRUE(s.scale == 1.0 && s.rotation == Mat3::Identity() && s.translation.isZero(0));
  EXPECT_EQ(DescribeGauge(ref, s), "the images held fixed");
}

TEST(GaugeHold, ColmapKeepsTheFirstPoseAndTheSecondXTranslationReadInFileOrder) {
  const CameraSide in = RandomSide(5, 6);
  const std::vector<int32_t> read_order = {3, 1, 0, 2, 4};
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kColmap, read_order);
  ASSERT_EQ(ref.hold, GaugeHold::kColmap);
  EXPECT_EQ(ref.anchor, 3);
  EXPECT_EQ(ref.second, 1);
  CameraSide solved = Moved(in, kWorld, 0.02);
  const Similarity back = GaugeMapping(ref, solved);
  MoveCameras(back, &solved);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(solved.camera(3)[k], in.camera(3)[k], 1e-13);
  EXPECT_NEAR(solved.camera(1)[3], in.camera(1)[3], 1e-13);
  // The others moved apart; the frame is not the mean's.
  EXPECT_GT(std::abs(solved.camera(1)[4] - in.camera(1)[4]), 1e-4);
  EXPECT_EQ(DescribeGauge(ref, back, std::vector<int64_t>{10, 20, 30, 40, 50}).substr(0, 63),
            "COLMAP's: image 40's pose and image 20's x translation (the opt");
  EXPECT_EQ(DescribeGauge(ref, back).substr(0, 52), "COLMAP's: image 3 (0-based)'s pose and image 1 (0-ba");
}

TEST(GaugeHold, FreeHoldsNothing) {
  const CameraSide in = RandomSide(4, 8);
  const GaugeReference ref = TakeGaugeReference(in, GaugeRule::kFree);
  const Similarity s = GaugeMapping(ref, Moved(in, kWorld, 0.0));
  EXPECT_TRUE(s.scale == 1.0 && s.rotation == Mat3::Identity() && s.translation.isZero(0));
  EXPECT_EQ(DescribeGauge(ref, s), "free (--gauge free): where LM ended");
}

}  // namespace
}  // namespace dba
