// The two-level preconditioner against its dense definition
// M⁻¹ = B⁻¹ + Rᵀ (R S Rᵀ)⁻¹ R, on mixed block sizes.
#include "dba/solver/two_level_preconditioner.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
#include <random>
#include <memory>
#include <set>
#include <stdexcept>

#include "dba/solver/pcg.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

// `sizes`: the block sizes drawn from (empty: the default mix).
BsmcMatrix Spd(int rows, int band, uint32_t seed, std::vector<int32_t> sizes = {}, double fill = 0.6) {
  testing::RandomBsmcOptions o;
  o.block_rows = rows;
  if (!sizes.empty()) o.sizes = std::move(sizes);
  o.fill = fill;
  o.band = band;
  o.positive_definite = true;
  o.seed = seed;
  return testing::MakeRandomBsmc(o);
}

// N_i as a dense matrix, size x (size + 1 with a scale column) (identity
// when `bases` is empty or not rigid).
Eigen::MatrixXd DenseBasis(const std::vector<CoarseRowBasis>& bases, int32_t i, int size) {
  const bool scale = !bases.empty() && bases[i].scale;
  Eigen::MatrixXd N = Eigen::MatrixXd::Identity(size, size + (scale ? 1 : 0));
  if (bases.empty() || !bases[i].rigid) return N;
  N.topLeftCorner(6, 6) << Eigen::Matrix3d::Zero(), bases[i].A, bases[i].B, bases[i].C;
  if (scale) N.block(3, size, 3, 1) = bases[i].D;
  return N;
}

// R: one row per coarse unknown; block (aggregate of i, i) is N_iᵀ.
Eigen::MatrixXd Restriction(const BsmcMatrix& S, const TwoLevelPreconditioner& M,
                            const std::vector<CoarseRowBasis>& bases = {}) {
  const BsmcMatrix& C = M.coarse();
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(C.num_rows(), S.num_rows());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const Eigen::MatrixXd N = DenseBasis(bases, i, S.block_size(i));
    R.block(C.scalar_offset(M.aggregate()[i]), S.scalar_offset(i), N.cols(), N.rows()) = N.transpose();
  }
  return R;
}

// Random rigid bases on the rows of 6 to 9 unknowns, every other one with a
// scale column; identity elsewhere.
std::vector<CoarseRowBasis> RandomRigidBases(const BsmcMatrix& S, uint32_t seed) {
  std::srand(seed);
  std::vector<CoarseRowBasis> bases(S.num_block_rows());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    if (S.block_size(i) < 6) continue;
    bases[i].rigid = true;
    bases[i].A = Eigen::Matrix3d::Random() + 2 * Eigen::Matrix3d::Identity();
    bases[i].B = Eigen::Matrix3d::Random() - 2 * Eigen::Matrix3d::Identity();
    bases[i].C = Eigen::Matrix3d::Random();
    bases[i].scale = i % 2 == 0;
    bases[i].D = Eigen::Vector3d::Random();
  }
  return bases;
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

// A 12 x 12 grid of 6-unknown rows (each joined to its right and lower
// neighbours), row i being cell `cell[i]`.
BsmcMatrix Grid(const std::vector<int32_t>& cell) {
  const int32_t n = static_cast<int32_t>(cell.size());
  std::vector<int32_t> row_of(n);
  for (int32_t i = 0; i < n; ++i) row_of[cell[i]] = i;
  std::vector<uint64_t> blocks;
  for (int32_t c = 0; c < n; ++c) {
    const int32_t x = c % 12, y = c / 12;
    const int32_t i = row_of[c];
    blocks.push_back(PackBlock(i, i));
    for (int32_t d : {x + 1 < 12 ? c + 1 : -1, y + 1 < 12 ? c + 12 : -1}) {
      if (d < 0) continue;
      const int32_t j = row_of[d];
      blocks.push_back(PackBlock(std::min(i, j), std::max(i, j)));
    }
  }
  std::sort(blocks.begin(), blocks.end());
  return BsmcMatrix::BuildFromPattern(std::vector<int32_t>(n, 6), blocks);
}

// The aggregates as sets of cells.
std::set<std::set<int32_t>> CellSets(const std::vector<int32_t>& aggregate,
                                     const std::vector<int32_t>& cell) {
  std::map<int32_t, std::set<int32_t>> members;
  for (size_t i = 0; i < aggregate.size(); ++i) members[aggregate[i]].insert(cell[i]);
  std::set<std::set<int32_t>> sets;
  for (auto& [a, cells] : members) sets.insert(cells);
  return sets;
}

// Rows met in a given order (the cells' order, as rcs/aggregation_order.h
// gives the cameras' places): the same aggregates however the rows are
// numbered; in row order they follow the numbering.
TEST(AggregateBlockRows, InAGivenOrderTheAggregatesDoNotDependOnTheNumbering) {
  std::vector<int32_t> cell(144), shuffled(144);
  std::iota(cell.begin(), cell.end(), 0);
  std::iota(shuffled.begin(), shuffled.end(), 0);
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(4));
  auto order_of = [](const std::vector<int32_t>& cells) {  // rows by cell
    std::vector<int32_t> order(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) order[cells[i]] = static_cast<int32_t>(i);
    return order;
  };
  const BsmcMatrix S = Grid(cell), T = Grid(shuffled);
  const auto by_cell = CellSets(AggregateBlockRows(S, 9, {}, -1, order_of(cell)), cell);
  EXPECT_EQ(CellSets(AggregateBlockRows(T, 9, {}, -1, order_of(shuffled)), shuffled), by_cell);
  EXPECT_EQ(CellSets(AggregateBlockRows(S, 9), cell), by_cell);  // row order is cell order
  EXPECT_NE(CellSets(AggregateBlockRows(T, 9), shuffled), by_cell);
}

class TwoLevelDefinition : public ::testing::TestWithParam<bool> {};

// With the identity bases (R sums each aggregate's rows) and with random
// rigid ones, with and without a scale column (R's blocks N_iᵀ), on 1 and 2
// threads.
TEST_P(TwoLevelDefinition, MatchesItsDenseDefinition) {
  const bool rigid = GetParam();
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const BsmcMatrix S = Spd(60, seed == 2 ? 0 : 4, seed);
    const std::vector<CoarseRowBasis> bases = rigid ? RandomRigidBases(S, seed) : std::vector<CoarseRowBasis>{};
    TwoLevelPreconditioner M(S, 5, seed == 3 ? 1 : 2, bases);
    M.Update(S);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
    std::map<int32_t, int> members;
    for (int32_t a : M.aggregate()) ++members[a];
    for (int32_t i = 0; rigid && i < S.num_block_rows(); ++i) {
      // A lone row's scale would be one of its translations.
      EXPECT_EQ(M.bases()[i].scale, bases[i].scale && members[M.aggregate()[i]] > 1) << "row " << i;
    }
    if (rigid) {
      EXPECT_GT(std::count_if(M.bases().begin(), M.bases().end(),
                              [](const CoarseRowBasis& N) { return N.scale; }), 0) << "seed " << seed;
    }
    const Eigen::MatrixXd R = Restriction(S, M, M.bases());
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
        testing::SolveSpd(block_diagonal, r) + R.transpose() * testing::SolveSpd(coarse, R * r);
    Eigen::VectorXd z(S.num_rows());
    M.Apply(r.data(), z.data());
    EXPECT_LT((z - expected).norm(), 1e-10 * expected.norm()) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Bases, TwoLevelDefinition, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return info.param ? "Rigid" : "Identity";
                         });

TEST(TwoLevelPreconditioner, RigidRowsAggregateOnlyWithRigidRows) {
  const BsmcMatrix S = Spd(120, 4, 5);
  std::vector<uint8_t> rigid(S.num_block_rows());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) rigid[i] = i % 3 == 0;
  const std::vector<int32_t> aggregate = AggregateBlockRows(S, 6, rigid);
  std::map<int32_t, std::set<uint8_t>> kinds;
  for (int32_t i = 0; i < S.num_block_rows(); ++i) kinds[aggregate[i]].insert(rigid[i]);
  for (const auto& [a, k] : kinds) EXPECT_EQ(k.size(), 1u) << "aggregate " << a;
}

TEST(TwoLevelPreconditioner, RefusesARigidBasisOnASmallRow) {
  const BsmcMatrix S = Spd(40, 3, 2);
  std::vector<CoarseRowBasis> bases(S.num_block_rows());
  int32_t small = 0;
  while (S.block_size(small) >= 6) ++small;
  bases[small].rigid = true;
  EXPECT_THROW(TwoLevelPreconditioner(S, 5, 1, bases), std::invalid_argument);
  EXPECT_THROW(TwoLevelPreconditioner(S, 5, 1, std::vector<CoarseRowBasis>(3)), std::invalid_argument);
  bases[small].rigid = false;
  int32_t large = 0;
  while (S.block_size(large) < 6) ++large;
  bases[large].scale = true;  // a scale column needs the rigid basis
  EXPECT_THROW(TwoLevelPreconditioner(S, 5, 1, bases), std::invalid_argument);
}

// One aggregate's scale is the global gauge: no scale coordinate then.
TEST(TwoLevelPreconditioner, ScaleNeedsTwoAggregates) {
  const BsmcMatrix S = Spd(24, 3, 4, {9}, 1.0);  // connected rows of 9
  std::vector<CoarseRowBasis> bases = RandomRigidBases(S, 4);
  for (CoarseRowBasis& N : bases) N.scale = N.rigid;
  const TwoLevelPreconditioner one(S, 1000, 1, bases);
  for (const CoarseRowBasis& N : one.bases()) EXPECT_FALSE(N.scale);
  const TwoLevelPreconditioner several(S, 4, 1, bases);
  EXPECT_TRUE(std::any_of(several.bases().begin(), several.bases().end(),
                          [](const CoarseRowBasis& N) { return N.scale; }));
}

// Above 256 rows the coarse solve runs beside block-Jacobi and R, Rᵀ are
// split over the threads: the same z as on one thread, to the last bit.
TEST(TwoLevelPreconditioner, ApplyIsTheSameOnAnyNumberOfThreads) {
  const BsmcMatrix S = Spd(400, 3, 11);
  const std::vector<CoarseRowBasis> bases = RandomRigidBases(S, 11);
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 3.0);
  Eigen::VectorXd one(S.num_rows());
  for (int threads : {1, 2, 3}) {
    TwoLevelPreconditioner M(S, 6, threads, bases);
    M.Update(S);
    Eigen::VectorXd z = Eigen::VectorXd::Constant(S.num_rows(), 7.0);
    M.Apply(r.data(), z.data());
    if (threads == 1) {
      one = z;
      EXPECT_GT(z.norm(), 0.0);
      continue;
    }
    EXPECT_EQ((z - one).cwiseAbs().maxCoeff(), 0.0) << threads << " threads";
  }
}

// Update's values at a place lent for them (block-Jacobi's inverses, the
// coarse matrix; the second thread's partial sum of it stays its own):
// every lent double written, and the same z as in storage of its own,
// before and after.
TEST(TwoLevelPreconditioner, ALentPlaceGivesTheSameZAsItsOwnStorage) {
  // Enough blocks (2 x 2^14) for Update to sum the coarse matrix on 2 threads.
  const BsmcMatrix S = Spd(1500, 60, 5, {3, 6}, 0.5);
  ASSERT_GE(S.num_blocks(), 2 << 14);
  TwoLevelPreconditioner M(S, 6, 2);
  int64_t inverses = 0;
  for (int32_t i = 0; i < S.num_block_rows(); ++i) inverses += int64_t{S.block_size(i)} * S.block_size(i);
  EXPECT_EQ(M.NumericDoubles(), inverses + M.coarse().num_values());
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 3.0);
  auto apply = [&](std::vector<double>* lent) {
    M.PlaceNumeric(lent == nullptr ? nullptr : lent->data());
    M.Update(S);
    Eigen::VectorXd z(S.num_rows());
    M.Apply(r.data(), z.data());
    M.ReturnNumericPages();
    return z;
  };
  const Eigen::VectorXd own = apply(nullptr);
  std::vector<double> lent(M.NumericDoubles(), std::nan(""));
  EXPECT_EQ(apply(&lent), own);
  EXPECT_EQ(std::count_if(lent.begin(), lent.end(), [](double v) { return std::isnan(v); }), 0);
  std::fill(lent.begin(), lent.end(), std::nan(""));  // the lender's again
  EXPECT_EQ(apply(nullptr), own);
}

// Update given a smaller team than it asks for (here: inside another
// parallel region, nested regions inactive, so a team of one) still sums
// every part of the coarse matrix: the same z.
TEST(TwoLevelPreconditioner, UpdateOnASmallerTeamGivesTheSameZ) {
  const BsmcMatrix S = Spd(1500, 60, 5, {3, 6}, 0.5);
  ASSERT_GE(S.num_blocks(), 2 << 14);  // two parts of the coarse sum
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(S.num_rows(), -1.0, 3.0);
  TwoLevelPreconditioner M(S, 6, 2);
  M.Update(S);
  Eigen::VectorXd expected(S.num_rows()), z(S.num_rows());
  M.Apply(r.data(), expected.data());
  const int levels = omp_get_max_active_levels();
  omp_set_max_active_levels(1);
  int inner_team = 0;
#pragma omp parallel num_threads(2)
#pragma omp single
  {
#pragma omp parallel num_threads(2)
#pragma omp single
    inner_team = omp_get_num_threads();
    M.Update(S);
    M.Apply(r.data(), z.data());
  }
  omp_set_max_active_levels(levels);
  EXPECT_EQ(inner_team, 1);
  EXPECT_EQ(z, expected);
}

// A coarse solver that fails (as one whose rank was lost does), in its
// solves or already in its factorization.
class FailingCoarseSolver : public CholeskySolver {
 public:
  explicit FailingCoarseSolver(bool in_factorize = false) : in_factorize_(in_factorize) {}
  bool Factorize(const BsmcMatrix&) override {
    if (in_factorize_) throw std::runtime_error("coarse factorization failed");
    return true;
  }
  void SolveFactored(const double*, double*) override {
    throw std::runtime_error("coarse solve failed");
  }
  LinearSolverType type() const override { return LinearSolverType::kAuto; }
  int64_t MemoryBytes() const override { return 0; }

 private:
  bool in_factorize_;
};

// The coarse solve runs inside a parallel region; its exception still
// reaches Apply's caller instead of ending the process.
TEST(TwoLevelPreconditioner, CoarseSolveFailureReachesTheCaller) {
  const BsmcMatrix S = Spd(300, 3, 5);
  const TwoLevelPreconditioner whole(S, 6, 1);
  std::vector<int32_t> sizes(whole.num_aggregates());
  for (int32_t a = 0; a < whole.num_aggregates(); ++a) sizes[a] = whole.coarse().block_size(a);
  TwoLevelPreconditioner M(S, 2, S.num_block_rows(), whole.aggregate(), sizes, {},
                           std::make_unique<FailingCoarseSolver>());
  M.Update(S);
  const Eigen::VectorXd r = Eigen::VectorXd::Ones(S.num_rows());
  Eigen::VectorXd z(S.num_rows());
  EXPECT_THROW(M.Apply(r.data(), z.data()), std::runtime_error);
  // The factorization runs beside block-Jacobi's update: the same.
  TwoLevelPreconditioner F(S, 2, S.num_block_rows(), whole.aggregate(), sizes, {},
                           std::make_unique<FailingCoarseSolver>(true));
  EXPECT_THROW(F.Update(S), std::runtime_error);
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
