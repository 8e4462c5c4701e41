// A residual on one camera's pose alone (a camera-centre prior,
// rcs/camera_centre_prior.h) adds to that camera's row of the RCS (paper
// eq. 4: one more residual in the camera's block, none on the points): with
// its loss-corrected Jacobian J on the pose's step (δω, δC) and residual r,
//
//   S_cc[0:6, 0:6] += JᵀJ,  b_c -= Jᵀr,  g_c += Jᵀr,  diag(U)_c += diag(JᵀJ).
//
// One process and the gathered RCS add it where the whole system is; the RCS
// spread over ranks (cluster/distributed_rcs.h) has the row's owner add it.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace dba {

struct PoseRowTerm {
  int64_t image = 0;  // the camera, 0-based
  int32_t row = -1;   // its RCS row in global numbering, once known (-1: fixed)
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> JtJ = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();  // Jᵀr
};

// Adds `t` to a row whose diagonal block (block_size², row-major, the pose
// first) and vectors (block_size entries each) start at the pointers.
inline void AddPoseRowTerm(const PoseRowTerm& t, int block_size, double* diagonal_block,
                           double* b, double* gradient, double* jtj_diagonal) {
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) diagonal_block[i * block_size + j] += t.JtJ(i, j);
    b[i] -= t.g[i];
    gradient[i] += t.g[i];
    jtj_diagonal[i] += t.JtJ(i, i);
  }
}

}  // namespace dba
