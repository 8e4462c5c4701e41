// Selected inversion against the dense inverse: every entry on the factor's
// pattern (diagonal blocks and the blocks between rows the factor couples),
// for mixed block sizes, banded and scattered patterns, CHOLMOD's factor or
// Eigen's; entries outside the pattern refused.
#include "dba/solver/selected_inversion.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <stdexcept>

#include "dba/solver/sparse_cholesky.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

CholeskyFactor Factor(const BsmcMatrix& S) {
  SparseCholeskySolver solver(S);
  EXPECT_TRUE(solver.Factorize(S));
  return solver.TakeFactor();
}

TEST(SelectedInversion, EqualsTheDenseInverseOnTheFactorsPattern) {
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    testing::RandomBsmcOptions o;
    o.block_rows = 30 + 10 * seed;
    o.fill = 0.12;
    o.band = seed % 2 == 0 ? 5 : 0;
    o.positive_definite = true;
    o.seed = seed;
    const BsmcMatrix S = testing::MakeRandomBsmc(o);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S);
    const Eigen::MatrixXd inverse = dense.llt().solve(Eigen::MatrixXd::Identity(dense.rows(), dense.cols()));
    CholeskyFactor f = Factor(S);
    const int64_t nonzeros = static_cast<int64_t>(f.row_idx.size());
    InvertOnPattern(&f);
    // Every entry on the pattern, by the factor's positions.
    double worst = 0.0;
    for (int64_t j = 0; j < f.size(); ++j) {
      for (int64_t p = f.col_ptr[j]; p < f.col_ptr[j + 1]; ++p) {
        const double expected = inverse(f.perm[f.row_idx[p]], f.perm[j]);
        worst = std::max(worst, std::abs(f.values[p] - expected));
      }
    }
    const double scale = inverse.diagonal().cwiseAbs().maxCoeff();
    EXPECT_LE(worst, 1e-12 * scale) << "seed " << seed;
    // Every diagonal block and every stored block of S, by S's indices.
    const InverseOnPattern z(std::move(f));
    EXPECT_EQ(z.nonzeros(), nonzeros);
    for (int32_t i = 0; i < S.num_block_rows(); ++i) {
      for (int64_t blk = S.row_begin(i); blk < S.row_end(i); ++blk) {
        const int32_t j = S.block_col(blk);
        for (int a = 0; a < S.block_size(i); ++a) {
          for (int c = 0; c < S.block_size(j); ++c) {
            const int64_t r = S.scalar_offset(i) + a, s = S.scalar_offset(j) + c;
            ASSERT_NEAR(z.At(r, s), inverse(r, s), 1e-12 * scale) << r << ", " << s;
            ASSERT_EQ(z.At(s, r), z.At(r, s));
          }
        }
      }
    }
  }
}

// Two rows nothing couples (a block diagonal matrix: no fill): their entry is
// not on the pattern, and asking for it is an error, not a zero.
TEST(SelectedInversion, RefusesAnEntryOutsideThePattern) {
  testing::RandomBsmcOptions o;
  o.block_rows = 6;
  o.sizes = {3};
  o.fill = 0.0;
  o.positive_definite = true;
  const BsmcMatrix S = testing::MakeRandomBsmc(o);
  CholeskyFactor f = Factor(S);
  InvertOnPattern(&f);
  const InverseOnPattern z(std::move(f));
  EXPECT_NO_THROW(z.At(0, 2));
  EXPECT_THROW(z.At(0, 3), std::out_of_range);
}

TEST(SelectedInversion, RefusesAFactorWithoutItsDiagonalFirst) {
  CholeskyFactor f;
  f.perm = {0, 1};
  f.col_ptr = {0, 2, 3};
  f.row_idx = {1, 0, 1};
  f.values = {0.5, -2.0, 1.0};  // column 0's diagonal is -2 once sorted
  EXPECT_THROW(SortFactorColumns(&f), std::logic_error);
}

}  // namespace
}  // namespace dba
