// The RCS formed point by point in BSMC (paper eq. 4) against the Schur
// complement of the dense damped normal equations.
#include "dba/rcs/form_rcs.h"
#include "dba/problem/fixings.h"

#include <algorithm>
#include <gtest/gtest.h>

#include <bit>

#include "dba/io/read_problem.h"
#include "dba/problem/point_order.h"
#include "dba/testing/scattered_survey.h"
#include "dba/synthetic/uav_generator.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

testing::SyntheticProblem PerturbedProblem(uint32_t seed) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 7;
  o.num_points = 60;
  o.max_track = 5;
  o.pixel_noise = 1.0;
  o.rotation_perturbation = 0.01;
  o.translation_perturbation = 0.05;
  o.point_perturbation = 0.05;
  o.intrinsics_perturbation = 0.01;
  o.seed = seed;
  return testing::MakeSyntheticBal(o);
}

double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

// Point 0 gets a second observation by its first camera, 3.6 px away.
void SeePointZeroTwiceByItsFirstCamera(Problem* problem) {
  const int32_t cam = problem->obs_camera[0];
  problem->obs_camera.insert(problem->obs_camera.begin() + 1, cam);
  problem->obs_pixel.insert(problem->obs_pixel.begin() + 2,
                            {problem->obs_pixel[0] + 3.0, problem->obs_pixel[1] - 2.0});
  for (size_t k = 1; k < problem->point_offsets.size(); ++k) ++problem->point_offsets[k];
}

class FormRcsTest : public ::testing::TestWithParam<double> {};

TEST_P(FormRcsTest, MatchesDenseSchurComplement) {
  const double lambda = GetParam();
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    Problem problem = PerturbedProblem(seed).problem;
    const DampingBounds bounds;
    RcsSystem sys = RcsSystem::ForProblem(problem);
    FormRcs(problem, lambda, bounds, 2, &sys);
    DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);

    const testing::DenseNormalEquations dense =
        testing::BuildDenseNormalEquations(problem, lambda, bounds);
    const Eigen::MatrixXd S_ref = dense.ReducedCameraMatrix();
    EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), S_ref), 1e-10)
        << "seed " << seed;
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10);
    const Eigen::VectorXd g_c = Eigen::Map<const Eigen::VectorXd>(
        sys.camera_side_gradient.data(), sys.camera_side_gradient.size());
    EXPECT_LT(RelativeError(g_c, dense.g.head(dense.num_camera_params)), 1e-12);
    EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost);
    const Eigen::VectorXd g_p = dense.g.tail(dense.g.size() - dense.num_camera_params);
    EXPECT_NEAR(sys.max_abs_point_gradient, g_p.cwiseAbs().maxCoeff(),
                1e-12 * g_p.cwiseAbs().maxCoeff());
  }
}

INSTANTIATE_TEST_SUITE_P(Damping, FormRcsTest, ::testing::Values(1e-4, 1.0, 1e3),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return std::string("lambda_") +
                                  (info.param < 1 ? "1e_4" : info.param > 1 ? "1e3" : "1");
                         });

TEST(FormRcs, DuplicateCameraInATrackCountsBothObservations) {
  Problem problem = PerturbedProblem(9).problem;
  // Point 0 seen twice by its first camera, at a shifted pixel.
  SeePointZeroTwiceByItsFirstCamera(&problem);
  const DampingBounds bounds;
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 0.1, bounds, 1, &sys);
  DampCameraBlocks(0.1, bounds, sys.camera_side_jtj_diagonal, &sys.S);
  const auto dense = testing::BuildDenseNormalEquations(problem, 0.1, bounds);
  EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10);
}

TEST(FormRcs, RefillingGivesTheSameValues) {
  Problem problem = PerturbedProblem(5).problem;
  const DampingBounds bounds;
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 1e-2, bounds, 1, &sys);
  const std::vector<double> first(sys.S.values().begin(), sys.S.values().end()), first_b = sys.b;
  FormRcs(problem, 1e-2, bounds, 1, &sys);
  EXPECT_TRUE(std::ranges::equal(sys.S.values(), first));
  EXPECT_EQ(sys.b, first_b);
}


// The photogrammetric model: pose blocks (6) and intrinsic blocks (≤ 5) of
// different sizes in one BSMC matrix, with pose-pose, pose-intrinsics and
// intrinsics-intrinsics blocks, against the dense Schur complement, for each
// way of holding parameters fixed.
struct PhotoCase {
  const char* name;
  uint8_t free_intrinsics;       // mask of unknowns for every group
  std::vector<int> fixed_images;
};

class PhotoFormRcsTest : public ::testing::TestWithParam<PhotoCase> {};

// A small problem of 7 images and 3 intrinsic groups in lens model `m`,
// perturbed.
Problem LensProblem(LensModel m, uint32_t seed) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 7;
  o.geometry.num_points = 60;
  o.geometry.max_track = 5;
  o.geometry.pixel_noise = 1.0;
  o.geometry.rotation_perturbation = 0.01;
  o.geometry.translation_perturbation = 0.05;
  o.geometry.point_perturbation = 0.05;
  o.geometry.seed = seed;
  o.num_groups = 3;
  o.focal_perturbation = 0.01;
  o.principal_perturbation = 2.0;
  o.distortion_perturbation = 0.05;
  o.lens_model = m;
  return testing::MakeSyntheticPhoto(o).problem;
}

Problem PhotoProblem(const PhotoCase& c, uint32_t seed) {
  Problem p = LensProblem(LensModel::kRadial, seed);
  p.fixed_intrinsics.assign(p.num_groups(), static_cast<uint8_t>(kAllIntrinsics & ~c.free_intrinsics));
  p.fixed_cameras.assign(p.num_images(), 0);
  for (int i : c.fixed_images) p.fixed_cameras[i] = 1;
  return p;
}

TEST_P(PhotoFormRcsTest, MatchesDenseSchurComplement) {
  const PhotoCase& c = GetParam();
  for (double lambda : {1e-4, 1.0}) {
    for (uint32_t seed = 1; seed <= 2; ++seed) {
      const Problem problem = PhotoProblem(c, seed);
      const DampingBounds bounds;
      RcsSystem sys = RcsSystem::ForProblem(problem);
      FormRcs(problem, lambda, bounds, 2, &sys);
      DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);
      const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
      ASSERT_EQ(sys.S.num_rows(), dense.num_camera_params);
      EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10)
          << c.name << " seed " << seed << " lambda " << lambda;
      const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
      EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10);
      const Eigen::VectorXd g_c = Eigen::Map<const Eigen::VectorXd>(
          sys.camera_side_gradient.data(), sys.camera_side_gradient.size());
      EXPECT_LT(RelativeError(g_c, dense.g.head(dense.num_camera_params)), 1e-12);
      EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Fixings, PhotoFormRcsTest,
    ::testing::Values(PhotoCase{"all_free", kAllIntrinsics, {}},
                      PhotoCase{"principal_point_fixed",
                                kIntrinsicF | kIntrinsicK1 | kIntrinsicK2, {}},
                      PhotoCase{"only_focal_free", kIntrinsicF, {2}},
                      PhotoCase{"intrinsics_fixed", 0, {}},
                      PhotoCase{"two_images_fixed", kAllIntrinsics, {0, 4}}),
    [](const ::testing::TestParamInfo<PhotoCase>& info) { return info.param.name; });

// Every lens model: pose-intrinsics and intrinsics-intrinsics blocks of its
// size, against the dense Schur complement.
void ExpectMatchesDense(const Problem& problem, const std::string& what) {
  for (double lambda : {1e-4, 1.0}) {
    const DampingBounds bounds;
    RcsSystem sys = RcsSystem::ForProblem(problem);
    FormRcs(problem, lambda, bounds, 2, &sys);
    DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);
    const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
    ASSERT_EQ(sys.S.num_rows(), dense.num_camera_params) << what;
    EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10)
        << what << " lambda " << lambda;
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10) << what;
    EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost) << what;
  }
}

TEST(FormRcs, EveryLensModelMatchesDenseSchurComplement) {
  for (const LensModelInfo& info : LensModels()) {
    const Problem problem = LensProblem(info.id, 1);
    const UnknownLayout layout(problem);
    // 7 poses, then a row per group with its model's unknowns (none for
    // EQUIRECTANGULAR, whose w and h are not unknowns).
    const int unknowns = std::popcount(LensModelParamMask(info.id));
    EXPECT_EQ(layout.num_block_rows(), 7 + (unknowns > 0 ? 3 : 0)) << info.name;
    EXPECT_EQ(layout.max_intrinsics_block(), unknowns) << info.name;
    ExpectMatchesDense(problem, info.name);
  }
}

// Groups of different models and sizes in one problem (the kernels' width is
// the largest block's), some parameters fixed by name.
TEST(FormRcs, MixedLensModelsAndFixedParametersMatchDenseSchurComplement) {
  Problem problem = LensProblem(LensModel::kRadTanThinPrismFisheye, 2);
  // FISHEYE and THIN_PRISM_FISHEYE read the first 4 and 12 of the values.
  problem.group_models = {LensModel::kFisheye, LensModel::kThinPrismFisheye,
                          LensModel::kRadTanThinPrismFisheye};
  ApplyFixings(Fixings{{3}, {{2, {"k3", "k4", "k5", "p0"}}, {1, {"cy"}}}}, &problem);
  const UnknownLayout layout(problem);
  EXPECT_EQ(layout.block_size(layout.intrinsics_row(0)), 4);
  EXPECT_EQ(layout.block_size(layout.intrinsics_row(1)), 11);
  EXPECT_EQ(layout.block_size(layout.intrinsics_row(2)), 12);
  ExpectMatchesDense(problem, "mixed");
}

TEST(FormRcs, PhotoRowsAndBlockSizes) {
  const Problem problem =
      PhotoProblem({"", kIntrinsicF | kIntrinsicK1, {1}}, 3);
  const RcsSystem sys = RcsSystem::ForProblem(problem);
  // 6 free poses of 6, then 3 groups of 2 free parameters.
  ASSERT_EQ(sys.S.num_block_rows(), 9);
  for (int32_t r = 0; r < 6; ++r) EXPECT_EQ(sys.S.block_size(r), 6);
  for (int32_t r = 6; r < 9; ++r) EXPECT_EQ(sys.S.block_size(r), 2);
  EXPECT_EQ(sys.S.num_rows(), 6 * 6 + 3 * 2);
  EXPECT_EQ(sys.layout.camera_row(1), -1);
  EXPECT_EQ(sys.layout.camera_row(2), 1);
}


TEST(FormRcs, PhotoDuplicateImageInATrackCountsBothObservations) {
  Problem problem = PhotoProblem({"", kAllIntrinsics, {}}, 5);
  // COLMAP models hold such tracks.
  SeePointZeroTwiceByItsFirstCamera(&problem);
  const DampingBounds bounds;
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 0.1, bounds, 2, &sys);
  DampCameraBlocks(0.1, bounds, sys.camera_side_jtj_diagonal, &sys.S);
  const auto dense = testing::BuildDenseNormalEquations(problem, 0.1, bounds);
  EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10);
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
  EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10);
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// A perturbed problem with every fifth observation moved by 6-20 px, so
// residuals fall on both sides of a loss scale of 2 px.
Problem WithGrossErrors(Problem problem) {
  for (int64_t o = 0; o < problem.num_observations(); o += 5) {
    problem.obs_pixel[2 * o] += 6.0 + static_cast<double>(o % 15);
    problem.obs_pixel[2 * o + 1] -= 4.0;
  }
  return problem;
}

class RobustFormRcsTest : public ::testing::TestWithParam<LossType> {};

// The RCS of the robust cost (Triggs-corrected residuals and Jacobians)
// against the Schur complement of the dense robust normal equations
// Σ Jᵀ Ω J + λ D, both camera models.
TEST_P(RobustFormRcsTest, MatchesDenseRobustSchurComplement) {
  const RobustLoss loss{GetParam(), 2.0};
  const DampingBounds bounds;
  for (bool photo : {false, true}) {
    const Problem problem =
        WithGrossErrors(photo ? PhotoProblem(PhotoCase{"all_free", kAllIntrinsics, {1}}, 3)
                              : PerturbedProblem(5).problem);
    RcsSystem sys = RcsSystem::ForProblem(problem);
    FormRcs(problem, 1e-2, bounds, 2, &sys, loss);
    DampCameraBlocks(1e-2, bounds, sys.camera_side_jtj_diagonal, &sys.S);
    const auto dense = testing::BuildDenseNormalEquations(problem, 1e-2, bounds, loss);
    const std::string what = std::string(LossName(loss.type)) + (photo ? " photo" : " bal");
    EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10)
        << what;
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10) << what;
    EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost) << what;
    EXPECT_NEAR(sys.residuals.squared, dense.r.squaredNorm(), 1e-12 * dense.r.squaredNorm());
    double inliers = 0;
    for (int64_t a = 0; a < problem.num_observations(); ++a) {
      inliers += loss.trivial() || dense.r.segment<2>(2 * a).squaredNorm() <= 4.0;
    }
    EXPECT_EQ(sys.residuals.inliers, inliers) << what;
    if (!loss.trivial()) {
      EXPECT_LT(inliers, problem.num_observations()) << what;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Losses, RobustFormRcsTest,
                         ::testing::Values(LossType::kTrivial, LossType::kHuber, LossType::kSoftL1,
                                           LossType::kCauchy, LossType::kArctan, LossType::kTukey),
                         [](const ::testing::TestParamInfo<LossType>& info) {
                           return std::string(LossName(info.param));
                         });

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// |a - b|∞ / |a|∞ of two vectors (0 for two empty ones).
double VectorRelativeError(std::span<const double> a, std::span<const double> b) {
  EXPECT_EQ(a.size(), b.size());
  double diff = 0.0, scale = 0.0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return scale > 0 ? diff / scale : diff;
}

struct ThreadCase {
  bool photo;
  int threads;
};
void PrintTo(const ThreadCase& c, std::ostream* out) {
  *out << (c.photo ? "photo" : "bal") << " with " << c.threads << " threads";
}

class FormRcsThreadsTest : public ::testing::TestWithParam<ThreadCase> {};

// Every field of the formed system is the same with 1 and with 2, 4 or 8
// threads (up to the order of the sums), both camera models, a robust loss
// on the photogrammetric one.
TEST_P(FormRcsThreadsTest, EveryFieldMatchesOneThread) {
  const ThreadCase& c = GetParam();
  const Problem problem = c.photo ? PhotoProblem(PhotoCase{"all_free", kAllIntrinsics, {2}}, 4)
                                     : PerturbedProblem(4).problem;
  const RobustLoss loss = c.photo ? RobustLoss{LossType::kCauchy, 1.0} : RobustLoss{};
  const DampingBounds bounds;
  RcsSystem one = RcsSystem::ForProblem(problem), many = RcsSystem::ForProblem(problem);
  FormRcs(problem, 1e-2, bounds, 1, &one, loss);
  FormRcs(problem, 1e-2, bounds, c.threads, &many, loss);
  EXPECT_LT(VectorRelativeError(one.S.values(), many.S.values()), 1e-13) << "S";
  EXPECT_LT(VectorRelativeError(one.b, many.b), 1e-13) << "b";
  EXPECT_LT(VectorRelativeError(one.camera_side_gradient, many.camera_side_gradient), 1e-13) << "g_c";
  EXPECT_LT(VectorRelativeError(one.camera_side_jtj_diagonal, many.camera_side_jtj_diagonal), 1e-13)
      << "diag U";
  EXPECT_NEAR(one.cost, many.cost, 1e-13 * one.cost);
  EXPECT_NEAR(one.residuals.squared, many.residuals.squared, 1e-13 * one.residuals.squared);
  EXPECT_NEAR(one.residuals.inlier_squared, many.residuals.inlier_squared,
              1e-13 * one.residuals.squared);
  EXPECT_EQ(one.residuals.inliers, many.residuals.inliers);
  EXPECT_EQ(one.max_abs_point_gradient, many.max_abs_point_gradient);
}

INSTANTIATE_TEST_SUITE_P(
    ModelsAndThreads, FormRcsThreadsTest,
    ::testing::Values(ThreadCase{false, 2}, ThreadCase{false, 4}, ThreadCase{false, 8},
                      ThreadCase{true, 2}, ThreadCase{true, 4}, ThreadCase{true, 8}),
    [](const ::testing::TestParamInfo<ThreadCase>& info) {
      return std::string(info.param.photo ? "photo" : "bal") + "_" +
             std::to_string(info.param.threads) + "_threads";
    });

// An RCS too large for the threads' private copies: only the rows that
// more than one thread's range of points touches are shared (FindSharedRows):
// a survey's points are ordered along its strips, so most camera rows
// belong to one thread; the photogrammetric model's intrinsics rows are
// shared. On 8 threads the later threads' shared rows pass an eighth of the
// RCS, so they are summed under row locks: the values are those of one
// thread to rounding. (The threads' own sums: FormRcsSeams below.)
class FormRcsLocksTest : public ::testing::TestWithParam<CameraModel> {};

TEST_P(FormRcsLocksTest, LocksOnlySharedRowsAndMatchesOneThread) {
  UavSurveyOptions o;
  o.images = 3000;
  o.features_per_image = 100;
  o.forward_overlap = 0.6;
  o.side_overlap = 0.3;
  o.model = GetParam();
  const std::string path = testing::TempPath("form_rcs_locks.dba");
  GenerateUavSurvey(o, path, "");
  const Problem problem = ReadProblem(path);
  const DampingBounds bounds;
  RcsSystem one = RcsSystem::ForProblem(problem), many = RcsSystem::ForProblem(problem);
  constexpr int kThreads = 8;
  ASSERT_EQ(FormationCopyBytes(many.S.num_values(), many.S.num_rows(), kThreads), 0)
      << "the survey's RCS is small enough for private copies: no locks to test";
  FormRcs(problem, 1e-3, bounds, 1, &one);
  FormRcs(problem, 1e-3, bounds, kThreads, &many);
  ASSERT_EQ(many.shared_rows_threads, kThreads);
  // A row is shared exactly when the threads of the points touching it
  // (thread t forms points [n t / 8, n (t + 1) / 8)) are not all one.
  const int64_t n = problem.num_points();
  std::vector<int> lowest(many.S.num_block_rows(), kThreads), highest(many.S.num_block_rows(), -1);
  for (int t = 0; t < kThreads; ++t) {
    for (int64_t k = n * t / kThreads; k < n * (t + 1) / kThreads; ++k) {
      for (int64_t a = problem.point_offsets[k]; a < problem.point_offsets[k + 1]; ++a) {
        const int32_t i = problem.obs_camera[a];
        for (const int32_t row :
             {many.layout.camera_row(i), problem.model == CameraModel::kPhoto
                                             ? many.layout.intrinsics_row(problem.camera_intrinsics[i])
                                             : -1}) {
          if (row < 0) continue;
          lowest[row] = std::min(lowest[row], t), highest[row] = std::max(highest[row], t);
        }
      }
    }
  }
  for (int32_t r = 0; r < many.S.num_block_rows(); ++r) {
    ASSERT_EQ(many.shared_rows[r], lowest[r] < highest[r] ? 1 : 0) << "row " << r;
  }
  const int64_t shared = std::count(many.shared_rows.begin(), many.shared_rows.end(), 1);
  EXPECT_GT(shared, 0);
  EXPECT_LT(shared, many.S.num_block_rows() / 2);
  EXPECT_LT(VectorRelativeError(one.S.values(), many.S.values()), 1e-13) << "S";
  EXPECT_LT(VectorRelativeError(one.b, many.b), 1e-13) << "b";
  EXPECT_LT(VectorRelativeError(one.camera_side_gradient, many.camera_side_gradient), 1e-13);
  EXPECT_NEAR(one.cost, many.cost, 1e-13 * one.cost);
  // 8 threads' ranges cut this survey's strips: the shared rows the later
  // threads touch pass an eighth of the RCS, and are summed under locks.
  EXPECT_EQ(many.seam_doubles, 0);
  // Formed again (the shared rows kept), the same values to rounding.
  const std::vector<double> first(many.S.values().begin(), many.S.values().end());
  FormRcs(problem, 1e-3, bounds, kThreads, &many);
  EXPECT_LT(VectorRelativeError(first, many.S.values()), 1e-13);
}

// A walked survey past the private copies' 32 MiB on 2 threads: the rows
// both threads touch are few (the walk's ranges meet along one seam), the
// second thread sums them in its own pages, added after the first's: one
// thread's values to rounding, and formed again the same bits.
TEST(FormRcsSeams, AWalkedSurveyFormsTheSameBitsEveryTime) {
  Problem problem = testing::MakeScatteredSurvey("form_rcs_seams.dba", 2200, 120, 4, 2).scattered;
  const std::vector<int64_t> walk = PointWalk(problem);
  ASSERT_FALSE(walk.empty());
  PermutePoints(walk, &problem);
  PermuteCameras(CamerasInPointOrder(problem), &problem);
  const DampingBounds bounds;
  RcsSystem one = RcsSystem::ForProblem(problem), two = RcsSystem::ForProblem(problem);
  ASSERT_EQ(FormationCopyBytes(two.S.num_values(), two.S.num_rows(), 2), 0) << "small enough for copies";
  FormRcs(problem, 1e-3, bounds, 1, &one);
  FormRcs(problem, 1e-3, bounds, 2, &two);
  ASSERT_GT(two.seam_doubles, 0);
  EXPECT_LT(two.shared_rows_later_doubles * 8,
            FormationSeamBytesLimit(two.S.num_values(), two.S.num_rows(), 2));
  EXPECT_LT(VectorRelativeError(one.S.values(), two.S.values()), 1e-13) << "S";
  EXPECT_LT(VectorRelativeError(one.b, two.b), 1e-13) << "b";
  EXPECT_LT(VectorRelativeError(one.camera_side_jtj_diagonal, two.camera_side_jtj_diagonal), 1e-13);
  const std::vector<double> first(two.S.values().begin(), two.S.values().end());
  const std::vector<double> first_b = two.b, first_g = two.camera_side_gradient;
  for (int again = 0; again < 3; ++again) {
    FormRcs(problem, 1e-3, bounds, 2, &two);
    EXPECT_TRUE(std::equal(first.begin(), first.end(), two.S.values().begin()));
    EXPECT_EQ(first_b, two.b);
    EXPECT_EQ(first_g, two.camera_side_gradient);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, FormRcsLocksTest,
                         ::testing::Values(CameraModel::kBal, CameraModel::kPhoto),
                         [](const ::testing::TestParamInfo<CameraModel>& info) {
                           return std::string(info.param == CameraModel::kBal ? "bal" : "photo");
                         });

}  // namespace
}  // namespace dba
