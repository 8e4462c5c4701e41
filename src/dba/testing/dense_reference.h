// Dense references for tests: the full Jacobian, the damped normal equations
// (paper eq. 1 and 3) and their Schur complement (eq. 4), computed the
// textbook way with dense matrices. Only for small problems. Columns: the
// camera-side unknowns in UnknownLayout order (fixed parameters have none),
// then the points.
#pragma once

#include <Eigen/Core>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/problem/bal_problem.h"
#include "dba/rcs/eliminate_point.h"

namespace dba::testing {

struct DenseNormalEquations {
  Eigen::MatrixXd J;        // 2 num_obs x (camera-side unknowns + 3 num_points)
  Eigen::VectorXd r;        // residuals
  Eigen::MatrixXd H;        // JᵀJ + λ D,  D = clamp(diag JᵀJ)
  Eigen::VectorXd g;        // Jᵀ r
  int num_camera_params = 0;
  double cost = 0.0;

  // Schur complement of the point block: U - W V⁻¹ Wᵀ and -g_c + W V⁻¹ g_p.
  Eigen::MatrixXd ReducedCameraMatrix() const;
  Eigen::VectorXd ReducedRhs() const;
  // Full solution of H δ = -g.
  Eigen::VectorXd SolveStep() const;
};

DenseNormalEquations BuildDenseNormalEquations(const BalProblem& problem,
                                               double lambda,
                                               const DampingBounds& bounds);

// The symmetric matrix stored in a BSMC, both triangles filled.
Eigen::MatrixXd DenseFromBsmc(const BsmcMatrix& S);

}  // namespace dba::testing
