// Camera-side unknowns the data do not determine, one block row at a time
// (docs/design.md §8): a row whose own diagonal block S_uu of the reduced
// camera system at the optimum is singular (an image with too few
// observations, an intrinsic parameter nothing observes). S is positive
// semi-definite, so each null vector n of S_uu is one of S itself, zero
// off the row (xᵀSx = 0 implies Sx = 0). Pinning one unknown per such
// direction (an identity row in S) makes the rest's inverse the generalized
// inverse's: the marginalization over those directions, whatever was
// pinned, since S_ru's columns lie in the range of S_uu. The row's own
// figures are then undetermined; every other block is exact.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {

struct UndeterminedUnknowns {
  std::vector<int32_t> rows;  // block rows with a singular diagonal block, ascending
  std::vector<Eigen::MatrixXd> null;  // per row: its null directions (orthonormal columns)
  std::vector<int64_t> pins;  // one scalar row of S per null direction
};

// Whether a point coupled to row `r`'s unknowns by W_r (block size × 3) is
// moved by r's null directions n (the null vector of H that extends n
// moves it by −V⁻¹ W_rᵀ n): then nothing determines it either.
bool MovedByNullDirections(const Eigen::MatrixXd& null, const Eigen::MatrixXd& W_r);

// A direction is null below 1e-12 of the block's largest eigenvalue; its
// pins are the unknowns a column-pivoted QR of the null basis picks.
UndeterminedUnknowns FindUndeterminedUnknowns(const BsmcMatrix& S);

}  // namespace dba
