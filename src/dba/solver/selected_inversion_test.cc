// Selected inversion against the dense inverse: every entry on the factor's
// pattern (diagonal blocks and the blocks between rows the factor couples),
// for mixed block sizes, banded and scattered patterns, CHOLMOD's
// supernodal factor (Eigen's simplicial one without CHOLMOD) and the same
// factor split into supernodes of one column; entries outside the pattern
// and a factor laid out otherwise refused.
#include "dba/solver/selected_inversion.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <stdexcept>

#include "dba/solver/sparse_cholesky.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

SupernodalFactor Factor(const BsmcMatrix& S) {
  SparseCholeskySolver solver(S);
  EXPECT_TRUE(solver.Factorize(S));
  return solver.TakeFactor();
}

// The same factor, each column a supernode of its own (its rows from the
// diagonal down).
SupernodalFactor ByColumns(const SupernodalFactor& f) {
  SupernodalFactor c;
  c.perm = f.perm;
  c.first_column = {0};
  c.row_begin = {0};
  c.value_begin = {0};
  std::vector<double> values;
  for (int64_t s = 0; s < f.num_supernodes(); ++s) {
    const int64_t nsrow = f.row_begin[s + 1] - f.row_begin[s];
    for (int64_t j = 0; j < f.first_column[s + 1] - f.first_column[s]; ++j) {
      for (int64_t a = j; a < nsrow; ++a) {
        c.rows.push_back(f.rows[f.row_begin[s] + a]);
        values.push_back(f.values[f.value_begin[s] + j * nsrow + a]);
      }
      c.first_column.push_back(c.first_column.back() + 1);
      c.row_begin.push_back(static_cast<int64_t>(c.rows.size()));
      c.value_begin.push_back(static_cast<int64_t>(values.size()));
    }
  }
  SetFactorValues(std::move(values), &c);
  return c;
}

// Every stored entry against the dense inverse, by the factor's positions.
double WorstEntry(const SupernodalFactor& z, const Eigen::MatrixXd& inverse) {
  double worst = 0.0;
  for (int64_t s = 0; s < z.num_supernodes(); ++s) {
    const int64_t nsrow = z.row_begin[s + 1] - z.row_begin[s];
    for (int64_t j = z.first_column[s]; j < z.first_column[s + 1]; ++j) {
      for (int64_t a = j - z.first_column[s]; a < nsrow; ++a) {
        const double value = z.values[z.value_begin[s] + (j - z.first_column[s]) * nsrow + a];
        const double expected = inverse(z.perm[z.rows[z.row_begin[s] + a]], z.perm[j]);
        worst = std::max(worst, std::abs(value - expected));
      }
    }
  }
  return worst;
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
    const Eigen::MatrixXd inverse = testing::Inverse(dense);
    SupernodalFactor f = Factor(S);
    SupernodalFactor columns = ByColumns(f);
    SupernodalFactor threaded = Factor(S);
    CheckFactorLayout(columns);
    const int64_t values = static_cast<int64_t>(f.values.size());
    InvertOnPattern(&f);
    InvertOnPattern(&columns, 3);
    InvertOnPattern(&threaded, 3);
    const double scale = inverse.diagonal().cwiseAbs().maxCoeff();
    EXPECT_LE(WorstEntry(f, inverse), 1e-12 * scale) << "seed " << seed;
    EXPECT_LE(WorstEntry(columns, inverse), 1e-12 * scale) << "seed " << seed;
    EXPECT_LE(WorstEntry(threaded, inverse), 1e-12 * scale) << "seed " << seed;
    // Every diagonal block and every stored block of S, by S's indices.
    const InverseOnPattern z(std::move(f));
    EXPECT_EQ(z.values(), values);
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
  SupernodalFactor f = Factor(S);
  InvertOnPattern(&f);
  const InverseOnPattern z(std::move(f));
  EXPECT_NO_THROW(z.At(0, 2));
  EXPECT_THROW(z.At(0, 3), std::out_of_range);
}

TEST(SelectedInversion, RefusesAFactorLaidOutOtherwise) {
  SupernodalFactor f;
  f.perm = {0, 1};
  f.first_column = {0, 1, 2};
  f.row_begin = {0, 2, 3};
  f.rows = {1, 0, 1};  // column 0's rows do not start with its diagonal
  f.value_begin = {0, 2, 3};
  SetFactorValues({2.0, 0.5, 1.0}, &f);
  EXPECT_THROW(CheckFactorLayout(f), std::logic_error);
  f.rows = {0, 1, 1};
  SetFactorValues({-2.0, 0.5, 1.0}, &f);  // a negative diagonal
  EXPECT_THROW(CheckFactorLayout(f), std::logic_error);
  SetFactorValues({2.0, 0.5, 1.0}, &f);
  EXPECT_NO_THROW(CheckFactorLayout(f));
}

}  // namespace
}  // namespace dba
