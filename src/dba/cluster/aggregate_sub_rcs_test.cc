// The sum of the sub-RCSs of any point partition equals the RCS formed from
// all points at once (paper section 5: the RCS is a sum over points).
#include "dba/cluster/aggregate_sub_rcs.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "dba/cluster/partition.h"
#include "dba/cluster/rank_share.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

class AggregateSubRcsTest
    : public ::testing::TestWithParam<std::tuple<int, PartitionScheme>> {};

TEST_P(AggregateSubRcsTest, SumOfSubRcsEqualsTheGlobalRcs) {
  const auto [groups, scheme] = GetParam();
  testing::SyntheticBalOptions o;
  o.num_cameras = 12;
  o.num_points = 150;
  o.pixel_noise = 1.0;
  o.point_perturbation = 0.05;
  o.rotation_perturbation = 0.01;
  const BalProblem problem = testing::MakeSyntheticBal(o).problem;
  const DampingBounds bounds;
  const double lambda = 0.01;

  RcsSystem direct = RcsSystem::ForProblem(problem);
  FormRcs(problem, lambda, bounds, 1, &direct);

  // Global structure = union of the mapped sub-patterns (as the main rank builds it).
  const std::vector<int32_t> group = PartitionPoints(problem, groups, scheme);
  std::vector<RankShare> shares;
  std::vector<RcsSystem> subs;
  std::vector<uint64_t> pattern;
  for (int32_t i = 0; i < problem.num_cameras(); ++i) pattern.push_back(PackBlock(i, i));
  for (int g = 0; g < groups; ++g) {
    shares.push_back(ExtractShare(problem, group, g));
    subs.push_back(RcsSystem::ForProblem(shares.back().problem));
    for (uint64_t b : BlockPattern(subs.back().S)) {
      pattern.push_back(PackBlock(shares.back().global_camera[PackedRow(b)],
                                  shares.back().global_camera[PackedCol(b)]));
    }
  }
  std::sort(pattern.begin(), pattern.end());
  pattern.erase(std::unique(pattern.begin(), pattern.end()), pattern.end());
  RcsSystem global = RcsSystem::ForPattern(UnknownLayout(problem), pattern);
  EXPECT_EQ(global.S.num_blocks(), direct.S.num_blocks());

  ClearRcs(&global);
  std::vector<double> message;
  for (int g = 0; g < groups; ++g) {
    FormRcs(shares[g].problem, lambda, bounds, 1, &subs[g]);
    const SubRcsMap map = MapSubRcs(BlockPattern(subs[g].S), shares[g].global_camera, global.S);
    PackSubRcs(subs[g], &message);
    ASSERT_EQ(static_cast<int64_t>(message.size()), map.PackedSize(global.S));
    AggregateSubRcs(map, message, &global);
  }
  const Eigen::MatrixXd a = testing::DenseFromBsmc(global.S);
  const Eigen::MatrixXd b = testing::DenseFromBsmc(direct.S);
  EXPECT_LT((a - b).norm(), 1e-12 * b.norm());
  for (size_t i = 0; i < direct.b.size(); ++i) {
    EXPECT_NEAR(global.b[i], direct.b[i], 1e-9 * (1 + std::abs(direct.b[i])));
    EXPECT_NEAR(global.camera_gradient[i], direct.camera_gradient[i],
                1e-9 * (1 + std::abs(direct.camera_gradient[i])));
    EXPECT_NEAR(global.camera_jtj_diagonal[i], direct.camera_jtj_diagonal[i],
                1e-9 * direct.camera_jtj_diagonal[i]);
  }
  EXPECT_NEAR(global.cost, direct.cost, 1e-12 * direct.cost);
  EXPECT_DOUBLE_EQ(global.max_abs_point_gradient, direct.max_abs_point_gradient);
}

INSTANTIATE_TEST_SUITE_P(
    Partitions, AggregateSubRcsTest,
    ::testing::Combine(::testing::Values(1, 2, 3, 5),
                       ::testing::Values(PartitionScheme::kEqual,
                                         PartitionScheme::kCameraLocality)));

}  // namespace
}  // namespace dba
