// Dense references for tests: the full Jacobian, the damped normal equations
// (paper eq. 1 and 3) and their Schur complement (eq. 4), computed the
// textbook way with dense matrices. Only for small problems. Columns: the
// camera-side unknowns in UnknownLayout order (fixed parameters have none),
// then the points.
#pragma once

#include <Eigen/Core>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/problem/problem.h"
#include "dba/rcs/eliminate_point.h"

namespace dba::testing {

struct DenseNormalEquations {
  // 2 num_obs + 3 num_point_priors rows (the control points' prior rows
  // w ∘ (X - X₀) last) x (camera-side unknowns + 3 num_points)
  Eigen::MatrixXd J;
  Eigen::VectorXd r;        // residuals
  Eigen::MatrixXd H;        // Jᵀ Ω J + λ D,  D = clamp(diag Jᵀ Ω J)
  Eigen::VectorXd g;        // Jᵀ Ω' r
  // With a robust loss ρ (rcs/robust_loss.h), per observation a at
  // s = |r_a|²: Ω'_a = ρ' I and the Gauss-Newton weight of Triggs's
  // second-order model, Ω_a = ρ' I + 2 ρ'' r_a r_aᵀ where ρ'' > 0 (else
  // ρ' I). The squared loss: Ω = Ω' = I.
  int num_camera_params = 0;
  double cost = 0.0;         // ½ Σ ρ(|r_a|²)

  // Schur complement of the point block: U - W V⁻¹ Wᵀ and -g_c + W V⁻¹ g_p.
  Eigen::MatrixXd ReducedCameraMatrix() const;
  Eigen::VectorXd ReducedRhs() const;
  // Full solution of H δ = -g.
  Eigen::VectorXd SolveStep() const;
};

DenseNormalEquations BuildDenseNormalEquations(const Problem& problem,
                                               double lambda,
                                               const DampingBounds& bounds,
                                               const RobustLoss& loss = RobustLoss());

// The symmetric matrix stored in a BSMC, both triangles filled.
Eigen::MatrixXd DenseFromBsmc(const BsmcMatrix& S);

// Dense references' factorizations, compiled once here: instantiated in a
// test file each costs it 5-9 s of compilation.
// A⁻¹ b for a symmetric positive definite A (Cholesky).
Eigen::VectorXd SolveSpd(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);
// A⁻¹ b for a symmetric A (LDLᵀ).
Eigen::VectorXd SolveSymmetric(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);
// A⁻¹ (LU with partial pivoting).
Eigen::MatrixXd Inverse(const Eigen::MatrixXd& A);
// A = V diag(values) Vᵀ for a symmetric A, values ascending.
struct SymmetricEigen {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
};
SymmetricEigen EigenOfSymmetric(const Eigen::MatrixXd& A);

}  // namespace dba::testing
