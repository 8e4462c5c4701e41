// Pose covariances against dense references: the inverse of S when two held
// images fix the frame; on a free network (and with one held image, the
// scale free) the unique generalized inverse of S with the inner constraints
// over the centres, from the bordered matrix [S Bᵀ; B 0] with B = Nᵀ W and N
// S's null space by a dense eigen-decomposition. BAL and photogrammetric
// cameras (shared intrinsics), 1e-8 of each block's largest diagonal entry.
#include "dba/precision/camera_covariance.h"

#include <gtest/gtest.h>


#include "dba/camera/pose_step.h"
#include "dba/camera/rotation.h"
#include "dba/precision/point_covariance.h"
#include "dba/problem/fixings.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

testing::SyntheticBalOptions Geometry() {
  testing::SyntheticBalOptions g;
  g.num_cameras = 8;
  g.num_points = 120;
  g.max_track = 5;
  g.pixel_noise = 0.5;
  g.rotation_perturbation = 1e-3;
  g.translation_perturbation = 1e-2;
  g.point_perturbation = 1e-2;
  return g;
}

RcsSystem FormedAt(const Problem& problem) {
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 0.0, DampingBounds{}, 1, &sys);
  return sys;
}

// The reference in (δω, δC): S's generalized inverse with B Σ = 0, B the
// inner constraints over the centres of S's `free` null directions.
Eigen::MatrixXd DenseReference(const RcsSystem& sys, int free) {
  const Eigen::MatrixXd S = testing::DenseFromBsmc(sys.S);
  const Eigen::Index n = S.rows();
  if (free == 0) return testing::Inverse(S);
  const testing::SymmetricEigen eigen = testing::EigenOfSymmetric(S);
  const Eigen::MatrixXd N = eigen.vectors.leftCols(free);
  // `free` null directions, far below the smallest determined one.
  const double null = std::abs(eigen.values[free - 1]);
  EXPECT_LT(null, 1e-13 * eigen.values[n - 1]);
  EXPECT_GT(eigen.values[free], 1e4 * null);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(free, n);
  for (int32_t r = 0; r < sys.layout.num_camera_rows(); ++r) {
    const int64_t o = sys.layout.row_offset(r) + 3;
    B.middleCols(o, 3) = N.middleRows(o, 3).transpose();
  }
  Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(n + free, n + free);
  bordered.topLeftCorner(n, n) = S;
  bordered.bottomLeftCorner(free, n) = B;
  bordered.topRightCorner(n, free) = B.transpose();
  return testing::Inverse(bordered).topLeftCorner(n, n);
}

// Each image's block of `cov` against `reference` (over `sys`'s layout;
// images without a row there skipped), in (θ, C).
int ExpectAgainst(const Problem& problem, const CameraCovariances& cov, const RcsSystem& sys,
                  const Eigen::MatrixXd& reference) {
  int compared = 0;
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    const int32_t r = sys.layout.camera_row(i);
    if (r < 0) continue;
    const double* pose = problem.camera(i);
    const Vec3 omega(pose[0], pose[1], pose[2]);
    Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
    T.topLeftCorner<3, 3>() = -AngleAxisToRotation(omega).transpose() * SO3LeftJacobian(omega);
    const Eigen::Matrix<double, 6, 6> expected =
        T * reference.block<6, 6>(sys.layout.row_offset(r), sys.layout.row_offset(r)) * T.transpose();
    const double scale = expected.diagonal().maxCoeff();
    EXPECT_TRUE(cov.pose[i].has_value()) << "image " << i;
    if (!cov.pose[i]) continue;
    EXPECT_LE((*cov.pose[i] - expected).cwiseAbs().maxCoeff(), 1e-8 * scale) << "image " << i;
    EXPECT_GT(cov.pose[i]->diagonal().minCoeff(), 0.0) << "image " << i;
    ++compared;
  }
  return compared;
}

void ExpectPoseBlocks(const Problem& problem, int free, std::optional<Vec3> centre = {}) {
  const RcsSystem sys = FormedAt(problem);
  const CameraCovariances cov = ComputeCameraCovariances(problem, sys, {free, centre});
  ASSERT_EQ(static_cast<int64_t>(cov.pose.size()), problem.num_images());
  EXPECT_GT(cov.factor_nonzeros, 0);
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    EXPECT_EQ(cov.pose[i].has_value(), sys.layout.camera_row(i) >= 0) << i;
  }
  EXPECT_GT(ExpectAgainst(problem, cov, sys, DenseReference(sys, free)), 1);
}

TEST(CameraCovariance, BalFreeNetworkEqualsTheInnerConstraintsInverse) {
  ExpectPoseBlocks(testing::MakeSyntheticBal(Geometry()).problem, 7);
}

TEST(CameraCovariance, PhotoFreeNetworkWithSharedIntrinsicsEqualsTheInnerConstraintsInverse) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  o.num_groups = 2;
  ExpectPoseBlocks(testing::MakeSyntheticPhoto(o).problem, 7);
}

TEST(CameraCovariance, TwoHeldImagesGiveTheInverseOfS) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  Problem problem = testing::MakeSyntheticPhoto(o).problem;
  Fixings f;
  f.images = {0, 3};
  ApplyFixings(f, &problem);
  ExpectPoseBlocks(problem, 0);
}

TEST(CameraCovariance, OneHeldImageLeavesTheScaleToTheInnerConstraint) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  Problem problem = testing::MakeSyntheticPhoto(o).problem;
  Fixings f;
  f.images = {2};
  ApplyFixings(f, &problem);
  ExpectPoseBlocks(problem, 1, CameraCentre(problem.camera(2)));
}

// A free network taken as held (0 free): S is singular, refused by name.
TEST(CameraCovariance, AFreeNetworkTakenAsHeldIsRefused) {
  const Problem problem = testing::MakeSyntheticBal(Geometry()).problem;
  const RcsSystem sys = FormedAt(problem);
  try {
    ComputeCameraCovariances(problem, sys, {0, {}});
    ADD_FAILURE() << "not refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the data do not determine every camera unknown (first: image "),
              std::string::npos)
        << e.what();
  }
}

// `problem` without image `image`'s observations but its first `keep`, those
// on points seen 3 times or more (`pairs`: on points seen exactly twice,
// then seen once more only: undetermined).
Problem KeepingOf(const Problem& problem, int32_t image, int keep, bool pairs = false) {
  Problem cut = problem;
  cut.points.clear(), cut.point_offsets = {0}, cut.obs_camera.clear(), cut.obs_pixel.clear();
  int kept = 0;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    const int64_t first = problem.point_offsets[k], end = problem.point_offsets[k + 1];
    for (int64_t a = first; a < end; ++a) {
      if (problem.obs_camera[a] == image && (kept == keep || (end - first < 3) != pairs)) continue;
      kept += problem.obs_camera[a] == image;
      cut.obs_camera.push_back(problem.obs_camera[a]);
      cut.obs_pixel.insert(cut.obs_pixel.end(), problem.pixel(a), problem.pixel(a) + 2);
    }
    cut.points.insert(cut.points.end(), problem.point(k), problem.point(k) + kPointSize);
    cut.point_offsets.push_back(cut.num_observations());
  }
  EXPECT_EQ(kept, keep);
  return cut;
}

// `problem` without image `image`'s observations, the image held.
Problem HeldWithout(const Problem& problem, int32_t image) {
  Problem without = KeepingOf(problem, image, 0);
  Fixings f;
  f.images = {image};
  ApplyFixings(f, &without);
  return without;
}

// An image whose observations cannot determine its pose (two points: four
// equations for six unknowns): marked undetermined, and every other block
// as if its observations were absent (it absorbs them): the inner-constraint
// inverse of the problem without them, the image held there (holding
// nothing). Alone in a block row of zeros it is the same.
TEST(CameraCovariance, AnUndeterminedCameraIsMarkedAndTheRestAsWithoutIt) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  const Problem problem = testing::MakeSyntheticPhoto(o).problem;
  for (int keep : {2, 0}) {
    const Problem cut = KeepingOf(problem, 5, keep);
    const CameraCovariances cov = ComputeCameraCovariances(cut, FormedAt(cut), {7, {}});
    EXPECT_EQ(cov.undetermined_images, std::vector<int64_t>{5});
    EXPECT_TRUE(cov.undetermined_groups.empty());
    EXPECT_FALSE(cov.pose[5].has_value());
    const RcsSystem sys = FormedAt(HeldWithout(problem, 5));
    EXPECT_EQ(ExpectAgainst(cut, cov, sys, DenseReference(sys, 7)), problem.num_images() - 1) << keep;
  }
}

// The points of such an image: as without its observations, those its
// undetermined directions move (seen by one other image) undetermined (NaN).
TEST(CameraCovariance, AnUndeterminedCamerasPointsAreAsWithoutIt) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  const Problem problem = testing::MakeSyntheticPhoto(o).problem;
  const Problem without = HeldWithout(problem, 5);
  const RcsSystem reference_sys = FormedAt(without);
  const CameraSideInverse reference(without, reference_sys, {7, {}}, 1);
  const std::vector<Eigen::Matrix3d> expected =
      PointCovariances(without, reference_sys.layout, RobustLoss(), reference, 1);
  for (bool pairs : {false, true}) {
    const Problem cut = KeepingOf(problem, 5, 2, pairs);
    const RcsSystem sys = FormedAt(cut);
    const CameraSideInverse inverse(cut, sys, {7, {}}, 1);
    const std::vector<Eigen::Matrix3d> points = PointCovariances(cut, sys.layout, RobustLoss(), inverse, 1);
    int moved = 0;  // undetermined with two observations: by the image's null directions
    for (int64_t k = 0; k < problem.num_points(); ++k) {
      ASSERT_EQ(points[k].allFinite(), expected[k].allFinite()) << "point " << k << (pairs ? " (pairs)" : "");
      if (!points[k].allFinite()) {
        moved += cut.point_offsets[k + 1] - cut.point_offsets[k] >= 2;
        continue;
      }
      const double scale = expected[k].diagonal().maxCoeff();
      EXPECT_LE((points[k] - expected[k]).cwiseAbs().maxCoeff(), 1e-8 * scale) << "point " << k;
    }
    EXPECT_EQ(moved, pairs ? 2 : 0);
  }
}

// An intrinsic parameter nothing observes (its column of J zero: S's row
// and column zero): its group marked undetermined and left out, every image
// as with the parameter held.
TEST(CameraCovariance, AnIntrinsicNothingObservesIsMarkedAndTheRestAsHeld) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  const Problem problem = testing::MakeSyntheticPhoto(o).problem;
  RcsSystem sys = FormedAt(problem);
  const int32_t g = sys.layout.intrinsics_row(1);
  ASSERT_GE(g, 0);
  const int64_t j = sys.S.scalar_offset(g);  // the group's first free parameter
  for (int32_t r = 0; r < sys.S.num_block_rows(); ++r) {
    for (int64_t b = sys.S.row_begin(r); b < sys.S.row_end(r); ++b) {
      const int32_t c = sys.S.block_col(b);
      double* v = sys.S.block_values(b);
      const int n = sys.S.block_size(c);
      if (r == g) std::fill(v, v + n, 0.0);                                   // row j
      if (c == g) for (int y = 0; y < sys.S.block_size(r); ++y) v[y * n] = 0.0;  // column j
    }
  }
  EXPECT_EQ(sys.S.scalar_offset(g), j);
  const CameraCovariances cov = ComputeCameraCovariances(problem, sys, {7, {}});
  EXPECT_EQ(cov.undetermined_groups, std::vector<int64_t>{1});
  EXPECT_TRUE(cov.undetermined_images.empty());
  ASSERT_EQ(cov.intrinsics.size(), 1u);
  EXPECT_EQ(cov.intrinsics[0].group, 0);
  Problem held = problem;
  Fixings f;
  f.intrinsics = {{1, {LensModelParamName(problem.group_model(1), sys.layout.intrinsics_free_index(1)[0])}}};
  ApplyFixings(f, &held);
  const RcsSystem reference = FormedAt(held);
  EXPECT_EQ(ExpectAgainst(problem, cov, reference, DenseReference(reference, 7)), problem.num_images());
}

// θ: the camera's attitude error about the world axes. A step δω moves the
// camera-to-world rotation by exp([θ]ₓ) with θ = −R(ω)ᵀ J_l(ω) δω (central
// differences).
TEST(CameraCovariance, AttitudeIsARotationAboutTheWorldAxes) {
  const Vec3 omega(0.3, -0.7, 1.1);
  const Mat3 T = -AngleAxisToRotation(omega).transpose() * SO3LeftJacobian(omega);
  for (int k = 0; k < 3; ++k) {
    const double h = 1e-6;
    const Vec3 step = h * Vec3::Unit(k);
    const Mat3 plus = AngleAxisToRotation(omega + step).transpose();
    const Mat3 minus = AngleAxisToRotation(omega - step).transpose();
    const Mat3 d = (plus - minus) / (2 * h) * AngleAxisToRotation(omega);  // [θ_k]ₓ
    const Vec3 theta(d(2, 1), d(0, 2), d(1, 0));
    EXPECT_LE((theta - T.col(k)).norm(), 1e-8) << k;
  }
}

// Under a similarity the centre block scales by s² and both turn by Q.
TEST(CameraCovariance, MovesWithTheGaugesSimilarity) {
  PoseCovariance sigma = PoseCovariance::Identity();
  sigma(0, 3) = sigma(3, 0) = 0.5;
  Similarity s;
  s.scale = 2.0;
  s.rotation = AngleAxisToRotation(Vec3(0.0, 0.0, M_PI / 2));
  const PoseCovariance moved = MovePoseCovariance(s, sigma);
  EXPECT_NEAR(moved(3, 3), 4.0, 1e-12);
  EXPECT_NEAR(moved(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(moved(1, 4), 2.0 * 0.5, 1e-12);  // x -> y under the quarter turn
}

}  // namespace
}  // namespace dba
