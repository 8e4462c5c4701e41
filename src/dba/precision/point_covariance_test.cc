// Every block the precision module gives against the dense inverse of the
// full normal matrix H = JᵀJ (cameras, intrinsics and points together):
// a photogrammetric survey with shared intrinsics, held by camera-centre
// priors (absolute: H⁻¹), by two held images (H⁻¹) and free (the bordered
// inverse of [H Bᵀ; B 0], B the inner constraints over the centres of H's
// dense null space); a BAL survey free. 1e-8 of each block's largest
// diagonal entry.
#include "dba/precision/point_covariance.h"

#include <gtest/gtest.h>

#include "dba/camera/pose_step.h"
#include "dba/camera/rotation.h"
#include "dba/precision/camera_covariance.h"
#include "dba/problem/fixings.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

// 7 images, 90 points seen 2-5 times, 0.5 px noise, a perturbed start.
testing::SyntheticBalOptions Geometry() {
  return {.num_cameras = 7, .num_points = 90, .max_track = 5, .pixel_noise = 0.5,
          .rotation_perturbation = 1e-3, .translation_perturbation = 1e-2,
          .point_perturbation = 1e-2};
}

Problem Photo() {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry();
  o.num_groups = 2;
  return testing::MakeSyntheticPhoto(o).problem;
}

// The full inverse under the datum: H⁻¹, or the bordered inverse's block.
Eigen::MatrixXd Reference(const Eigen::MatrixXd& H, const UnknownLayout& layout, int free) {
  if (free == 0) return testing::Inverse(H);
  const Eigen::Index n = H.rows();
  const testing::SymmetricEigen e = testing::EigenOfSymmetric(H);
  const double null = std::abs(e.values[free - 1]);  // `free` null directions, then a gap
  EXPECT_LT(null, 1e-13 * e.values[n - 1]);
  EXPECT_GT(e.values[free], 1e4 * null);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(free, n);
  for (int32_t r = 0; r < layout.num_camera_rows(); ++r) {
    const int64_t o = layout.row_offset(r) + 3;
    B.middleCols(o, 3) = e.vectors.block(o, 0, 3, free).transpose();
  }
  Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(n + free, n + free);
  bordered.topLeftCorner(n, n) = H;
  bordered.bottomLeftCorner(free, n) = B;
  bordered.topRightCorner(n, free) = B.transpose();
  return testing::Inverse(bordered).topLeftCorner(n, n);
}

double Relative(const Eigen::MatrixXd& got, const Eigen::MatrixXd& expected) {
  return (got - expected).cwiseAbs().maxCoeff() / expected.diagonal().maxCoeff();
}

// Every pose, intrinsics and point block against the reference; `prior`:
// a centre prior of this weight² on every free image (in S and H alike).
void ExpectEveryBlock(const Problem& problem, int free, double prior = 0.0) {
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 0.0, DampingBounds{}, 1, &sys);
  Eigen::MatrixXd H = testing::BuildDenseNormalEquations(problem, 0.0, DampingBounds{}).H;
  const UnknownLayout& layout = sys.layout;
  for (int32_t r = 0; prior > 0 && r < layout.num_camera_rows(); ++r) {
    double* d = sys.S.block_values(sys.S.diagonal_block(r));
    for (int a = 3; a < 6; ++a) d[a * 6 + a] += prior, H(layout.row_offset(r) + a, layout.row_offset(r) + a) += prior;
  }
  const Eigen::MatrixXd reference = Reference(H, layout, free);
  const CameraSideInverse inverse(problem, sys, {free, {}}, 2);
  const CameraCovariances cameras = CameraBlocks(problem, layout, inverse);
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    const int32_t r = layout.camera_row(i);
    if (r < 0) continue;
    const double* pose = problem.camera(i);
    const Vec3 omega(pose[0], pose[1], pose[2]);
    Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
    T.topLeftCorner<3, 3>() = -AngleAxisToRotation(omega).transpose() * SO3LeftJacobian(omega);
    const Eigen::MatrixXd expected = T * reference.block(layout.row_offset(r), layout.row_offset(r), 6, 6) * T.transpose();
    EXPECT_LE(Relative(*cameras.pose[i], expected), 1e-8) << "image " << i;
  }
  for (const IntrinsicsCovariance& c : cameras.intrinsics) {
    const int32_t r = layout.intrinsics_row(c.group);
    const Eigen::Index n = c.covariance.rows();
    EXPECT_EQ(static_cast<size_t>(n), c.parameters.size());
    EXPECT_LE(Relative(c.covariance, reference.block(layout.row_offset(r), layout.row_offset(r), n, n)), 1e-8)
        << "group " << c.group;
  }
  if (problem.model == CameraModel::kPhoto) EXPECT_FALSE(cameras.intrinsics.empty());
  const std::vector<Eigen::Matrix3d> points = PointCovariances(problem, layout, RobustLoss(), inverse, 2);
  ASSERT_EQ(static_cast<int64_t>(points.size()), problem.num_points());
  const int64_t c = layout.num_unknowns();
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    EXPECT_LE(Relative(points[k], reference.block(c + 3 * k, c + 3 * k, 3, 3)), 1e-8) << "point " << k;
  }
}

TEST(PointCovariance, PhotoWithCentrePriorsEqualsTheFullInverse) { ExpectEveryBlock(Photo(), 0, 1e4); }

TEST(PointCovariance, PhotoWithTwoHeldImagesEqualsTheFullInverse) {
  Problem problem = Photo();
  Fixings f;
  f.images = {1, 4};
  ApplyFixings(f, &problem);
  ExpectEveryBlock(problem, 0);
}

TEST(PointCovariance, PhotoFreeNetworkEqualsTheInnerConstraintsInverse) { ExpectEveryBlock(Photo(), 7); }

TEST(PointCovariance, BalFreeNetworkEqualsTheInnerConstraintsInverse) {
  ExpectEveryBlock(testing::MakeSyntheticBal(Geometry()).problem, 7);
}

// `problem` with point k's observations cut to its first `keep` (k < 0:
// none cut, point `drop` left out).
Problem Cut(const Problem& problem, int64_t k, int keep, int64_t drop = -1) {
  Problem cut = problem;
  cut.points.clear(), cut.point_offsets = {0}, cut.obs_camera.clear(), cut.obs_pixel.clear();
  for (int64_t q = 0; q < problem.num_points(); ++q) {
    if (q == drop) continue;
    const int64_t first = problem.point_offsets[q];
    const int64_t end = q == k ? first + keep : problem.point_offsets[q + 1];
    for (int64_t a = first; a < end; ++a) {
      cut.obs_camera.push_back(problem.obs_camera[a]);
      cut.obs_pixel.insert(cut.obs_pixel.end(), problem.pixel(a), problem.pixel(a) + 2);
    }
    cut.points.insert(cut.points.end(), problem.point(q), problem.point(q) + kPointSize);
    cut.point_offsets.push_back(cut.num_observations());
  }
  return cut;
}

// A point left with one observation (its V singular at the optimum): its
// line undetermined (NaN), and every other block as if it were absent (it
// absorbs its one observation, V⁺ in S); no NaN anywhere else.
TEST(PointCovariance, APointItsObservationsDoNotDetermineIsMarkedAndGivesNothing) {
  const Problem problem = Photo();
  const int64_t k = 11;
  ASSERT_GE(problem.point_offsets[k + 1] - problem.point_offsets[k], 2);
  const Problem one = Cut(problem, k, 1), absent = Cut(problem, -1, 0, k);
  const auto covariances = [](const Problem& p) {
    RcsSystem sys = RcsSystem::ForProblem(p);
    FormRcs(p, 0.0, DampingBounds{}, 1, &sys);
    const CameraSideInverse inverse(p, sys, {7, {}}, 2);
    return std::pair(CameraBlocks(p, sys.layout, inverse),
                     PointCovariances(p, sys.layout, RobustLoss(), inverse, 2));
  };
  const auto [cameras_one, points_one] = covariances(one);
  const auto [cameras_absent, points_absent] = covariances(absent);
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    ASSERT_TRUE(cameras_one.pose[i] && cameras_absent.pose[i]);
    EXPECT_LE(Relative(*cameras_one.pose[i], *cameras_absent.pose[i]), 1e-8) << "image " << i;
  }
  EXPECT_FALSE(points_one[k].allFinite());
  for (int64_t q = 0; q < problem.num_points(); ++q) {
    if (q == k) continue;
    EXPECT_LE(Relative(points_one[q], points_absent[q - (q > k)]), 1e-8) << "point " << q;
  }
}

}  // namespace
}  // namespace dba
