// Camera-centre priors (GNSS positions) in the solve, on the main rank: a
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
// A prior touches one camera's diagonal block: the RCS pattern and the point
// elimination are unchanged. One process and the gathered RCS: the terms go
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

// ½ Σ ρ(|r|²) of the priors at `cameras` (camera_size parameters per image,
// the pose first).
double CameraPriorsCost(const CameraPriors& priors, const std::vector<double>& cameras,
                        int camera_size);

class PriorWorkers : public PointWorkers {
 public:
  // `points` and `cameras` (the LM loop's current cameras, updated by it)
  // must outlive this object.
  PriorWorkers(PointWorkers* points, const std::vector<double>* cameras, int camera_size,
               const CameraPriors& priors);

  RcsSystem& FormRcs(double lambda) override;
  StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c,
                              const std::vector<double>& candidate_cameras) override;
  void FinishStep(bool accept) override { points_->FinishStep(accept); }
  // The points' solver: the priors are in the system FormRcs returned.
  std::unique_ptr<DampedRcsSolver> MakeDampedRcsSolver(RcsSystem& system,
                                                       const LinearSolverOptions& options,
                                                       RcsSolverChoice* choice) override {
    return points_->MakeDampedRcsSolver(system, options, choice);
  }

 private:
  PointWorkers* points_;
  const std::vector<double>* cameras_;
  int camera_size_;
  const CameraPriors& priors_;
  const RcsSystem* system_ = nullptr;  // of the last FormRcs
  // At the last FormRcs: each prior's corrected residual and Jacobian, and
  // the robust model's offset.
  std::vector<Vec3> r_;
  std::vector<CentrePriorJacobian> J_;
  double model_offset_ = 0.0;
};

}  // namespace dba
