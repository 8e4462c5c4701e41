// Random BSMC matrices for tests: mixed block sizes, a random upper block
// pattern (all diagonal blocks present), symmetric diagonal blocks.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba::testing {

struct RandomBsmcOptions {
  int block_rows = 20;
  std::vector<int32_t> sizes = {9, 6, 5, 3};  // drawn uniformly per row
  double fill = 0.3;        // probability of an off-diagonal block
  int band = 0;             // > 0: off-diagonal blocks only within this band
  bool positive_definite = false;  // diagonally dominant SPD
  uint32_t seed = 1;
};

BsmcMatrix MakeRandomBsmc(const RandomBsmcOptions& options);

}  // namespace dba::testing
