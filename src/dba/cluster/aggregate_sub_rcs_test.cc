// The sum of the sub-RCSs of any point partition, aggregated through the
// production mapping, equals the Schur complement of the dense normal
// equations of all points (paper section 5: the RCS is a sum over points),
// for BAL and for the photogrammetric model with fixed images and fixed
// intrinsics.
#include "dba/cluster/aggregate_sub_rcs.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "dba/cluster/partition.h"
#include "dba/cluster/rank_share.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

struct AggregationCase {
  bool photo;
  int groups;
  PartitionScheme scheme;
};
void PrintTo(const AggregationCase& c, std::ostream* out) {
  *out << (c.photo ? "photo with fixings" : "bal") << ", " << c.groups << " groups, "
       << (c.scheme == PartitionScheme::kEqual ? "equal" : "cameras");
}

Problem MakeProblem(bool photo) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 12;
  o.num_points = 150;
  o.pixel_noise = 1.0;
  o.point_perturbation = 0.05;
  o.rotation_perturbation = 0.01;
  if (!photo) return testing::MakeSyntheticBal(o).problem;
  testing::SyntheticPhotoOptions p;
  p.geometry = o;
  p.num_groups = 3;
  p.focal_perturbation = 0.01;
  p.principal_perturbation = 2.0;
  Problem problem = testing::MakeSyntheticPhoto(p).problem;
  // Fixings: two images held, the principal point of every group, and all of
  // group 2's intrinsics.
  problem.fixed_cameras.assign(problem.num_images(), 0);
  problem.fixed_cameras[0] = problem.fixed_cameras[5] = 1;
  problem.fixed_intrinsics.assign(problem.num_groups(), kIntrinsicCx | kIntrinsicCy);
  problem.fixed_intrinsics[2] = kAllIntrinsics;
  return problem;
}

class AggregateSubRcsTest : public ::testing::TestWithParam<AggregationCase> {};

// Through the production path (ExtractShare, each share's own RCS, rows
// mapped by entity, BuildGlobalRcs, PackSubRcs, AggregateSubRcs), the
// global system equals the Schur complement of the dense damped normal
// equations of the whole problem.
TEST_P(AggregateSubRcsTest, SumOfSubRcsEqualsTheDenseSchurComplement) {
  const AggregationCase& c = GetParam();
  const Problem problem = MakeProblem(c.photo);
  const DampingBounds bounds;
  const double lambda = 0.01;
  const UnknownLayout layout(problem);

  const std::vector<int32_t> group = PartitionPoints(problem, c.groups, c.scheme);
  std::vector<RankShare> shares;
  std::vector<RcsSystem> subs;
  std::vector<std::vector<uint64_t>> patterns;
  std::vector<std::vector<int32_t>> rows;
  for (int g = 0; g < c.groups; ++g) {
    shares.push_back(ExtractShare(problem, group, g));
    subs.push_back(RcsSystem::ForProblem(shares.back().problem));
    patterns.push_back(BlockPattern(subs.back().S));
    rows.push_back(layout.RowsOfEntities(subs.back().layout.RowEntities(
        shares.back().global_camera, shares.back().global_intrinsics)));
  }
  GlobalRcs global = BuildGlobalRcs(layout, patterns, rows);
  ClearRcs(&global.system);
  std::vector<double> message;
  for (int g = 0; g < c.groups; ++g) {
    FormRcs(shares[g].problem, lambda, bounds, 1, &subs[g]);
    PackSubRcs(subs[g], &message);
    ASSERT_EQ(static_cast<int64_t>(message.size()), global.maps[g].PackedSize(global.system.S));
    AggregateSubRcs(global.maps[g], message, &global.system);
  }
  RcsSystem& sys = global.system;
  DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);
  const testing::DenseNormalEquations dense =
      testing::BuildDenseNormalEquations(problem, lambda, bounds);
  const Eigen::MatrixXd S_ref = dense.ReducedCameraMatrix();
  EXPECT_LT((testing::DenseFromBsmc(sys.S) - S_ref).norm(), 1e-10 * S_ref.norm());
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
  EXPECT_LT((b - dense.ReducedRhs()).norm(), 1e-10 * dense.ReducedRhs().norm());
  const Eigen::VectorXd g_c = Eigen::Map<const Eigen::VectorXd>(sys.camera_side_gradient.data(),
                                                                sys.camera_side_gradient.size());
  EXPECT_LT((g_c - dense.g.head(dense.num_camera_params)).norm(),
            1e-10 * dense.g.head(dense.num_camera_params).norm());
  EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost);
  const Eigen::VectorXd g_p = dense.g.tail(dense.g.size() - dense.num_camera_params);
  EXPECT_NEAR(sys.max_abs_point_gradient, g_p.cwiseAbs().maxCoeff(),
              1e-12 * g_p.cwiseAbs().maxCoeff());
}

std::vector<AggregationCase> AggregationCases() {
  std::vector<AggregationCase> cases;
  for (bool photo : {false, true}) {
    for (int groups : {1, 2, 3, 5}) {
      for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
        cases.push_back({photo, groups, scheme});
      }
    }
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(
    Partitions, AggregateSubRcsTest, ::testing::ValuesIn(AggregationCases()),
    [](const ::testing::TestParamInfo<AggregationCase>& info) {
      return std::string(info.param.photo ? "photo_fixed" : "bal") + "_" +
             std::to_string(info.param.groups) + "_groups_" +
             (info.param.scheme == PartitionScheme::kEqual ? "equal" : "cameras");
    });

}  // namespace
}  // namespace dba
