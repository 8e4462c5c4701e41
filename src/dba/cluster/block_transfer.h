// A block of a BSMC matrix copied out or added in as it is or transposed:
// a share whose cameras are numbered by its walk (cluster/rank_share.h) has
// blocks (i, j), i <= j locally, whose global rows come the other way; the
// global RCS stores them as (j, i), transposed (docs/design.md §3, §4.1).
//
// Thread safety: pure functions over the blocks they are given.
#pragma once

#include <cstdint>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {

// Block b of `m` (row-major r x c) into `out` as it is, or transposed
// (row-major c x r); returns the end of what it wrote.
double* CopyBlock(const BsmcMatrix& m, int64_t b, bool transposed, double* out);
// Block b of `m` += `in`: values of its shape, or of its transpose's
// (CopyBlock's transposed layout); returns the end of what it read.
const double* AddToBlock(const double* in, bool transposed, int64_t b, BsmcMatrix* m);
// The block row that block b of `m` is in.
int32_t BlockRow(const BsmcMatrix& m, int64_t b);

}  // namespace dba
