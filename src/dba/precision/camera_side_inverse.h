// The camera side's covariance Σ_c = S⁻¹ at the optimum under the solve's
// datum (docs/design.md §8): S factored with d unknowns pinned (S_h), its
// inverse selected on the factor's pattern (solver/selected_inversion.h),
// and, when the data leave the frame free (d > 0), the inner constraints
// over the camera centres by the S-transformation
//
//   Σ = Σ_h − Y K Gᵀ − G Kᵀ Yᵀ + G N Gᵀ,
//   Y = Σ_h W G,  M = Gᵀ W G,  K = M⁻ᵀ,  N = M⁻¹ (Gᵀ W Y) M⁻ᵀ,
//
// G the null space of S from the same factor (g_k = e_k − S_h⁻¹ S e_k), W
// the selection of the centres. A point's block follows from its cameras':
// Σ_p = V⁻¹ + V⁻¹ Wᵀ Σ_h W V⁻¹ in the pinned datum, and its rows of G and Y
// are −V⁻¹ Wᵀ times theirs (a null direction moves each point as the
// cameras' optimal response: J_c g_c + J_p g_p = 0).
//
// Thread safety: const methods may run on several threads at once.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/problem/problem.h"
#include "dba/rcs/form_rcs.h"
#include "dba/precision/undetermined_unknowns.h"
#include "dba/solver/selected_inversion.h"

namespace dba {

// What the data leave free of the frame, as the solve's gauge knows it.
struct GaugeFreedom {
  int free = 7;                      // 7 (nothing holds it), 1 (scale), 0
  std::optional<Vec3> scale_centre;  // free == 1: the held image's centre
};

class CameraSideInverse {
 public:
  // Factors and inverts `rcs.S` of `side` at the optimum on `threads`
  // threads, the undetermined rows' null directions pinned. std::runtime_error
  // when S (with the pins) is still not positive definite.
  CameraSideInverse(const CameraSide& side, const RcsSystem& rcs, const GaugeFreedom& freedom,
                    int threads);
  // With the undetermined unknowns already found (FindUndeterminedUnknowns
  // of rcs.S).
  CameraSideInverse(const CameraSide& side, const RcsSystem& rcs, const GaugeFreedom& freedom,
                    int threads, UndeterminedUnknowns undetermined);
  // Σ_c over the camera-side unknowns `rows` (each pair on the factor's
  // pattern: within one block row, or two rows that share a point).
  Eigen::MatrixXd Block(std::span<const int64_t> rows) const;
  // A point's Σ_p, W (|rows| × 3) its coupling Σ_a J_e,aᵀ J_p,a to the
  // unknowns `rows`, V its Σ_a J_p,aᵀ J_p,a (undamped); NaN when V is
  // singular (rcs/eliminate_point.h PointDetermined) or an undetermined
  // row's null directions move it: undetermined.
  Eigen::Matrix3d PointBlock(std::span<const int64_t> rows, const Eigen::MatrixXd& W,
                             const Eigen::Matrix3d& V) const;

  int free() const { return free_; }
  // Block rows the data do not determine (precision/undetermined_unknowns.h):
  // their own blocks are not covariances; every other block is, with their
  // undetermined directions marginalized.
  bool undetermined(int32_t row) const { return undetermined_[row] != 0; }
  int64_t factor_values() const { return factor_values_; }
  double inversion_flops() const { return inversion_flops_; }
  double factor_seconds() const { return factor_seconds_; }  // to the factor and the datum's solves

 private:
  Eigen::MatrixXd Held(std::span<const int64_t> rows) const;  // Σ_h over rows
  // Whether an undetermined row among `rows` (sorted) moves the point W couples.
  bool MovedByUndetermined(std::span<const int64_t> rows, const Eigen::MatrixXd& W) const;
  // The datum's terms over rows whose G and Y rows are g and y.
  Eigen::MatrixXd DatumTerms(const Eigen::MatrixXd& g, const Eigen::MatrixXd& y) const;
  int free_ = 0;
  std::vector<uint8_t> pinned_, undetermined_;
  UndeterminedUnknowns null_;
  std::vector<int32_t> null_of_;  // per scalar row: its null_ entry where an undetermined row starts, else -1
  std::optional<InverseOnPattern> z_;
  Eigen::MatrixXd G_, Y_, K_, N_;  // the datum's (d columns; empty when absolute)
  int64_t factor_values_ = 0;
  double inversion_flops_ = 0.0, factor_seconds_ = 0.0;
};

}  // namespace dba
