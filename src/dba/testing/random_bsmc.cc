// Random BSMC matrices for tests; see random_bsmc.h.
#include "dba/testing/random_bsmc.h"

#include <cmath>
#include <random>

namespace dba::testing {

BsmcMatrix MakeRandomBsmc(const RandomBsmcOptions& o) {
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
  std::vector<int32_t> sizes(o.block_rows);
  for (int32_t& s : sizes) s = o.sizes[rng() % o.sizes.size()];
  std::vector<uint64_t> pattern;
  for (int i = 0; i < o.block_rows; ++i) {
    pattern.push_back(PackBlock(i, i));
    for (int j = i + 1; j < o.block_rows; ++j) {
      if (o.band > 0 && j - i > o.band) break;
      if (coin(rng) < o.fill) pattern.push_back(PackBlock(i, j));
    }
  }
  BsmcMatrix m = BsmcMatrix::BuildFromPattern(sizes, pattern);
  std::vector<double> row_abs_sum(m.num_rows(), 0.0);
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      const int ri = m.block_size(i), cj = m.block_size(j);
      double* v = m.block_values(b);
      for (int r = 0; r < ri; ++r) {
        for (int c = 0; c < cj; ++c) {
          // Diagonal blocks symmetric: fill the upper half, mirror it.
          if (j == i && c < r) {
            v[r * cj + c] = v[c * cj + r];
          } else {
            v[r * cj + c] = u(rng);
          }
          if (!(j == i && r == c)) {
            row_abs_sum[m.scalar_offset(i) + r] += std::abs(v[r * cj + c]);
            if (j != i) row_abs_sum[m.scalar_offset(j) + c] += std::abs(v[r * cj + c]);
          }
        }
      }
    }
  }
  if (o.positive_definite) {
    for (int32_t i = 0; i < m.num_block_rows(); ++i) {
      const int c = m.block_size(i);
      double* v = m.block_values(m.diagonal_block(i));
      for (int d = 0; d < c; ++d) v[d * c + d] = row_abs_sum[m.scalar_offset(i) + d] + 1.0;
    }
  }
  return m;
}

}  // namespace dba::testing
