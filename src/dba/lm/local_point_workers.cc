// Single-process PointWorkers; see local_point_workers.h.
#include "dba/lm/local_point_workers.h"

#include "dba/common/memory.h"

namespace dba {

LocalPointWorkers::LocalPointWorkers(Problem* problem,
                                     const DampingBounds& bounds,
                                     int num_threads, const RobustLoss& loss,
                                     const std::function<void(const RcsSystem&)>& before_values,
                                     bool values_at_first_form, bool lever_arm)
    : problem_(problem),
      bounds_(bounds),
      num_threads_(num_threads),
      loss_(loss),
      system_(RcsSystem::ForProblem(*problem, before_values, !values_at_first_form, lever_arm)) {}

RcsSystem& LocalPointWorkers::FormRcs(double lambda) {
  if (!system_.S.has_values()) system_.AllocateValues();
  dba::FormRcs(*problem_, lambda, bounds_, num_threads_, &system_, loss_);
  return system_;
}

StepEvaluation LocalPointWorkers::EvaluateStep(double lambda,
                                               const std::vector<double>& delta_c) {
  candidate_cameras_.resize(problem_->cameras.size());
  system_.layout.PlusCameraSide(problem_->cameras.data(), delta_c.data(),
                                candidate_cameras_.data());
  return BackSubstitute(*problem_, system_.layout, lambda, bounds_, delta_c, candidate_cameras_,
                        num_threads_, &candidate_points_, loss_);
}

void LocalPointWorkers::ReleaseRcsValues() {
  system_.S.ReleaseValues();
  for (std::vector<double>* v :
       {&system_.b, &system_.camera_side_gradient, &system_.camera_side_jtj_diagonal}) {
    std::vector<double>().swap(*v);
  }
}

void LocalPointWorkers::FinishStep(bool accept) {
  if (accept) {
    problem_->cameras.swap(candidate_cameras_);
    problem_->points.swap(candidate_points_);
  }
  // The next back-substitution rewrites every candidate point: until then
  // (the next formation and solve) their pages are the system's, unless the
  // solve borrows them.
  if (!candidate_points_lent_) {
    ReturnPages(candidate_points_.data(),
                static_cast<int64_t>(candidate_points_.size() * sizeof(double)));
  }
}

std::unique_ptr<DampedRcsSolver> LocalPointWorkers::MakeDampedRcsSolver(
    RcsSystem& system, const LinearSolverOptions& options, RcsSolverChoice* choice) {
  auto solver = std::make_unique<LocalDampedRcsSolver>(
      system.S, options, choice, &candidate_points_, static_cast<int64_t>(problem_->points.size()));
  candidate_points_lent_ = solver->borrows_idle();
  return solver;
}

}  // namespace dba
