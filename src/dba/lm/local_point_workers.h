// PointWorkers for one process: the rank holds every point, and its sub-RCS
// is the global RCS (no aggregation, no copy).
//
// Thread safety: one caller; the work inside uses `num_threads` threads.
#pragma once

#include "dba/lm/point_workers.h"
#include "dba/problem/problem.h"

namespace dba {

class LocalPointWorkers : public PointWorkers {
 public:
  // Builds the RCS structure (symbolic phase). `problem` must outlive this
  // object; its cameras and points are updated in place on accepted steps.
  // `loss`: the robust loss of every observation (rcs/robust_loss.h).
  // `before_values`: see RcsSystem::ForProblem. `values_at_first_form`:
  // S's values are allocated by the first FormRcs, not here (a rank of a
  // distributed RCS: its owned rows' symbolic phase then does not hold them
  // beside its sub-RCS's; at 1M on 8 ranks 0.75 GB each). `lever_arm`: the
  // RCS has the camera priors' lever arm's row (lm/prior_workers.h).
  LocalPointWorkers(Problem* problem, const DampingBounds& bounds,
                    int num_threads, const RobustLoss& loss = RobustLoss(),
                    const std::function<void(const RcsSystem&)>& before_values = {},
                    bool values_at_first_form = false, bool lever_arm = false);

  RcsSystem& FormRcs(double lambda) override;
  StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c) override;
  void FinishStep(bool accept) override;
  // The solver's storage for what it computes afresh each solve (PCG's
  // preconditioner values and vectors) is the candidate points' buffer,
  // idle from the step's end to the next back-substitution, where it fits:
  // it is then held throughout, and no pages go back and come again.
  std::unique_ptr<DampedRcsSolver> MakeDampedRcsSolver(RcsSystem& system,
                                                       const LinearSolverOptions& options,
                                                       RcsSolverChoice* choice) override;

  const RcsSystem& system() const { return system_; }
  // Frees the RCS's values until the next FormRcs (a rank whose sub-RCS has
  // gone to its rows' owners).
  void ReleaseRcsValues();
  int num_threads() const { return num_threads_; }
  // The linear solver borrows the candidate points' buffer (MakeDampedRcsSolver).
  bool candidate_points_lent() const { return candidate_points_lent_; }
  // The candidate points of the last EvaluateStep (or what the solver wrote there since).
  const std::vector<double>& candidate_points() const { return candidate_points_; }

 private:
  Problem* problem_;
  DampingBounds bounds_;
  int num_threads_;
  RobustLoss loss_;
  RcsSystem system_;
  std::vector<double> candidate_cameras_;
  std::vector<double> candidate_points_;
  bool candidate_points_lent_ = false;  // to the linear solver
};

}  // namespace dba
