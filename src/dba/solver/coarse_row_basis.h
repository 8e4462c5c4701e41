// The coordinates one RCS block row shares with its aggregate in the
// two-level preconditioner's coarse space (solver/two_level_preconditioner.h).
#pragma once

#include <Eigen/Core>

namespace dba {

// The basis N of one block row's unknowns in the coarse space: the identity,
// or (`rigid`, a row of at least 6 unknowns whose first six are a pose
// (ω, t))
//
//   N = [ 0  A  0 ]   columns: scene translation (3), scene rotation (3),
//       [ B  C  0 ]   the row's other unknowns as they are.
//       [ 0  0  I ]
struct CoarseRowBasis {
  bool rigid = false;
  Eigen::Matrix3d A, B, C;
};

}  // namespace dba
