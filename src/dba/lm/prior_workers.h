// Camera priors (GNSS antenna positions) in the solve, on the main rank: a
// PointWorkers around the points' workers (lm/point_workers.h: the same
// lifecycle) that adds each prior's term (rcs/camera_centre_prior.h) to what
// they return, under its own robust loss (rcs/robust_loss.h: the corrected
// residual r̃ and Jacobian J̃, as for an observation):
//
//   FormRcs       cost += ½ ρ(|r|²); for a camera that is an unknown, its
//                 row of the RCS gets rcs/pose_row_term.h's term: S_cc +=
//                 J̃ᵀ J̃, b_c -= J̃ᵀ r̃, gradient += J̃ᵀ r̃, diag(JᵀJ) +=
//                 diag(J̃ᵀ J̃)
//   EvaluateStep  model cost += ½ |r̃ + J̃ δ_c|² + ½ (ρ - |r̃|²), candidate
//                 cost += ½ ρ(|r(c ⊞ δ_c)|²)
//
// A prior touches one camera's (with rigs, frame's) diagonal block, and,
// when the antenna's lever arm is an unknown (the layout's last row), the
// lever arm's diagonal block and the (camera, lever arm) block:
//   S_ca += J̃_cᵀ J̃_a,  S_aa += J̃_aᵀ J̃_a,  b_a -= J̃_aᵀ r̃ (and its gradient
//   and diagonal); the lever arm's parameters are the LM's x's last three,
//   which the points' workers never see (their candidate is x without them).
// The point elimination is unchanged. One process and the gathered RCS: the terms go
// into the system the points' FormRcs returns. The RCS spread over ranks:
// the main rank hands them to the workers before FormRcs
// (PointWorkers::SetPoseTerms) and each row's owner adds its own.
//
// Thread safety: as PointWorkers (one caller).
#pragma once

#include <vector>

#include "dba/lm/point_workers.h"
#include "dba/rcs/camera_centre_prior.h"
#include "dba/rcs/robust_loss.h"

namespace dba {

// ½ Σ ρ(|r|²) of the priors at the camera side's parameters, with the
// priors' own lever arm.
double CameraPriorsCost(const CameraPriors& priors, const CameraSide& side);

class PriorWorkers : public PointWorkers {
 public:
  // `points`, `side` and `x` (the LM loop's current camera-side parameters,
  // updated by it: side.cameras, then the lever arm when priors.
  // refine_lever_arm) must outlive this object.
  PriorWorkers(PointWorkers* points, const std::vector<double>* x, const CameraSide& side,
               const CameraPriors& priors);

  RcsSystem& FormRcs(double lambda) override;
  StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c) override;
  void FinishStep(bool accept) override { points_->FinishStep(accept); }
  // The points' solver: the priors are in the system FormRcs returned.
  std::unique_ptr<DampedRcsSolver> MakeDampedRcsSolver(RcsSystem& system,
                                                       const LinearSolverOptions& options,
                                                       RcsSolverChoice* choice) override {
    return points_->MakeDampedRcsSolver(system, options, choice);
  }

 private:
  using Jacobian = Eigen::Matrix<double, 3, 9, Eigen::RowMajor>;  // ∂r/∂(δω, δC, a)
  PointWorkers* points_;
  const std::vector<double>* x_;
  const CameraPriors& priors_;
  std::vector<int64_t> pose_offset_;  // per prior, in x
  int64_t lever_offset_ = -1;         // the lever arm in x, when an unknown
  std::vector<double> candidate_;     // x ⊞ δ of the last EvaluateStep
  const RcsSystem* system_ = nullptr;  // of the last FormRcs
  // At the last FormRcs: each prior's corrected residual and Jacobian, and
  // the robust model's offset.
  std::vector<Vec3> r_;
  std::vector<Jacobian> J_;
  double model_offset_ = 0.0;

  Vec3 LeverArm(const std::vector<double>& x) const;
  void AddLeverArmTerms(RcsSystem* sys) const;
};

}  // namespace dba
