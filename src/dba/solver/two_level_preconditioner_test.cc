// The two-level preconditioner against its dense definition
// M⁻¹ = B⁻¹ + Rᵀ (R S Rᵀ)⁻¹ R, on mixed block sizes.
#include "dba/solver/two_level_preconditioner.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <map>
#include <set>

#include "dba/solver/pcg.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

BsmcMatrix Spd(int rows, int band, uint32_t seed) {
  testing::RandomBsmcOptions o;
  o.block_rows = rows;
  o.fill = 0.6;
  o.band = band;
  o.positive_definite = true;
  o.seed = seed;
  return testing::MakeRandomBsmc(o);
}

// R: one row per coarse unknown, summing each aggregate's block rows.
Eigen::MatrixXd Restriction(const BsmcMatrix& S, const TwoLevelPreconditioner& M) {
  const BsmcMatrix& C = M.coarse();
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(C.num_rows(), S.num_rows());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int32_t a = M.aggregate()[i];
    for (int d = 0; d < S.block_size(i); ++d) R(C.scalar_offset(a) + d, S.scalar_offset(i) + d) = 1;
  }
  return R;
}

TEST(AggregateBlockRows, GroupsConnectedRowsOfOneSize) {
  const BsmcMatrix S = Spd(200, 3, 1);
  const std::vector<int32_t> aggregate = AggregateBlockRows(S, 4);
  ASSERT_EQ(aggregate.size(), 200u);
  std::map<int32_t, std::set<int32_t>> members;
  for (int32_t i = 0; i < 200; ++i) members[aggregate[i]].insert(i);
  for (const auto& [a, rows] : members) {
    EXPECT_LE(rows.size(), 4u) << "aggregate " << a;
    for (int32_t i : rows) {
      EXPECT_EQ(S.block_size(i), S.block_size(*rows.begin())) << "aggregate " << a << " row " << i;
    }
  }
  EXPECT_LT(members.size(), 200u);  // some aggregation happened
}

TEST(TwoLevelPreconditioner, MatchesItsDenseDefinition) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const BsmcMatrix S = Spd(60, seed == 2 ? 0 : 4, seed);
    TwoLevelPreconditioner M(S, 5, 2);
    M.Update(S);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
    const Eigen::MatrixXd R = Restriction(S, M);
    const Eigen::MatrixXd coarse = R * dense * R.transpose();
    EXPECT_LT((testing::DenseFromBsmc(M.coarse()) - coarse).norm(), 1e-12 * coarse.norm())
        << "seed " << seed;
    Eigen::MatrixXd block_diagonal = Eigen::MatrixXd::Zero(dense.rows(), dense.cols());
    for (int32_t i = 0; i < S.num_block_rows(); ++i) {
      const int64_t o = S.scalar_offset(i);
      const int c = S.block_size(i);
      block_diagonal.block(o, o, c, c) = dense.block(o, o, c, c);
    }
    const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 3.0);
    const Eigen::VectorXd expected =
        block_diagonal.llt().solve(r) + R.transpose() * coarse.llt().solve(R * r);
    Eigen::VectorXd z(S.num_rows());
    M.Apply(r.data(), z.data());
    EXPECT_LT((z - expected).norm(), 1e-10 * expected.norm()) << "seed " << seed;
  }
}

TEST(TwoLevelPreconditioner, PcgConvergesWithIt) {
  const BsmcMatrix S = Spd(300, 3, 7);
  TwoLevelPreconditioner M(S, 8, 2);
  M.Update(S);
  const SymmetricMultiplier multiplier(S, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(S.num_rows(), -2.0, 1.0);
  Eigen::VectorXd y(S.num_rows());
  PcgOptions options;
  options.eta = 0.0;
  options.relative_tolerance = 1e-12;
  PcgScratch scratch;
  const PcgSummary s = SolvePcg(multiplier, M, b.data(), y.data(), options, &scratch);
  EXPECT_EQ(s.stop, PcgStop::kResidual);
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
  EXPECT_LT((dense * y - b).norm(), 1e-11 * b.norm());
}

}  // namespace
}  // namespace dba
