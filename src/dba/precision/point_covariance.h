// Each point's 3×3 covariance at the optimum (docs/design.md §8): with V its
// Σ_a J_p,aᵀ J_p,a and W its Σ_a J_e,aᵀ J_p,a over the camera-side unknowns
// its observations touch (the robust loss's corrected Jacobians, as S's),
//
//   Σ_p = V⁻¹ + V⁻¹ Wᵀ Σ_c W V⁻¹
//
// in the datum of the camera side's inverse (camera_side_inverse.h, which
// adds the datum's terms through the point's rows of the null space). Σ_c
// over one point's unknowns is on the factor's pattern: S couples them.
//
// Thread safety: pure function; runs on `threads` threads.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dba/precision/camera_side_inverse.h"
#include "dba/rcs/robust_loss.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

// Σ_p of every point of `problem` (no rigs) at its parameters, unit pixel
// variance.
std::vector<Eigen::Matrix3d> PointCovariances(const Problem& problem, const UnknownLayout& layout,
                                              const RobustLoss& loss, const CameraSideInverse& inverse,
                                              int threads = 1);
// The same for the points `which` only (e.g. the control points), in order.
std::vector<Eigen::Matrix3d> PointCovariancesOf(const Problem& problem, const UnknownLayout& layout,
                                                const RobustLoss& loss, const CameraSideInverse& inverse,
                                                const std::vector<int64_t>& which, int threads = 1);

}  // namespace dba
