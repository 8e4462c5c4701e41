// Blocks copied or added as they are or transposed; see block_transfer.h.
#include "dba/cluster/block_transfer.h"

#include <algorithm>

namespace dba {

int32_t BlockRow(const BsmcMatrix& m, int64_t b) {
  int32_t lo = 0, hi = m.num_block_rows();  // the last row whose first block is <= b
  while (hi - lo > 1) {
    const int32_t mid = lo + (hi - lo) / 2;
    (m.row_begin(mid) <= b ? lo : hi) = mid;
  }
  return lo;
}

double* CopyBlock(const BsmcMatrix& m, int64_t b, bool transposed, double* out) {
  const double* v = m.block_values(b);
  const int64_t n = m.value_offset(b + 1) - m.value_offset(b);
  if (!transposed) return std::copy(v, v + n, out);
  const int64_t rows = m.block_size(BlockRow(m, b)), cols = n / rows;
  for (int64_t c = 0; c < cols; ++c) {
    for (int64_t r = 0; r < rows; ++r) *out++ = v[r * cols + c];
  }
  return out;
}

const double* AddToBlock(const double* in, bool transposed, int64_t b, BsmcMatrix* m) {
  double* v = m->block_values(b);
  const int64_t n = m->value_offset(b + 1) - m->value_offset(b);
  if (!transposed) {
    for (int64_t k = 0; k < n; ++k) v[k] += in[k];
    return in + n;
  }
  const int64_t rows = m->block_size(BlockRow(*m, b)), cols = n / rows;
  for (int64_t c = 0; c < cols; ++c) {
    for (int64_t r = 0; r < rows; ++r) v[r * cols + c] += *in++;
  }
  return in;
}

}  // namespace dba
