// The coordinates one RCS block row shares with its aggregate in the
// two-level preconditioner's coarse space (solver/two_level_preconditioner.h).
#pragma once

#include <Eigen/Core>

namespace dba {

// The basis N of one block row's unknowns in the coarse space: the identity,
// or (`rigid`, a row of at least 6 unknowns whose first six are a pose's
// step (δω, δC), camera/pose_step.h)
//
//   N = [ 0  A  0  0 ]   columns: scene translation (3), scene rotation (3),
//       [ B  C  0  D ]   the row's other unknowns as they are, and (`scale`)
//       [ 0  0  I  0 ]   the scene's scale (1, last).
//
// A row with `scale` has one coarse coordinate more than unknowns.
struct CoarseRowBasis {
  bool rigid = false;
  bool scale = false;  // only with rigid
  Eigen::Matrix3d A, B, C;
  Eigen::Vector3d D = Eigen::Vector3d::Zero();
};

}  // namespace dba
