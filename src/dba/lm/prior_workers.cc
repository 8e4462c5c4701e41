// Camera-centre priors around the points' workers; see prior_workers.h.
#include "dba/lm/prior_workers.h"

namespace dba {

double CameraPriorsCost(const CameraPriors& priors, const std::vector<double>& cameras,
                        int camera_size) {
  double cost = 0.0;
  for (const CameraCentrePrior& p : priors.priors) {
    const Vec3 r = CentrePriorResidual(cameras.data() + int64_t{camera_size} * p.image, p, nullptr);
    cost += 0.5 * priors.loss.Rho(r.squaredNorm());
  }
  return cost;
}

PriorWorkers::PriorWorkers(PointWorkers* points, const std::vector<double>* cameras,
                           int camera_size, const CameraPriors& priors)
    : points_(points), cameras_(cameras), camera_size_(camera_size), priors_(priors) {}

RcsSystem& PriorWorkers::FormRcs(double lambda) {
  const size_t n = priors_.priors.size();
  r_.resize(n);
  J_.resize(n);
  std::vector<double> costs(n);
  std::vector<PoseRowTerm> terms(n);
  model_offset_ = 0.0;
  for (size_t x = 0; x < n; ++x) {
    const CameraCentrePrior& p = priors_.priors[x];
    const double* pose = cameras_->data() + int64_t{camera_size_} * p.image;
    Vec3 r = CentrePriorResidual(pose, p, &J_[x]);
    const double s = r.squaredNorm();
    double rho[3];
    priors_.loss.Evaluate(s, rho);
    costs[x] = 0.5 * rho[0];
    if (!priors_.loss.trivial()) {
      const LossCorrection correction(s, rho);
      correction.CorrectJacobian(r, &J_[x]);
      r = correction.Residual(r);
      model_offset_ += 0.5 * (rho[0] - r.squaredNorm());
    }
    r_[x] = r;
    terms[x].image = p.image;
    terms[x].JtJ = J_[x].transpose() * J_[x];
    terms[x].g = J_[x].transpose() * r;
  }
  // The RCS spread over ranks: its rows' owners add the terms as they sum
  // the rows; else they go into the system here.
  const bool owners_add = points_->TakesPoseTerms();
  if (owners_add) points_->SetPoseTerms(std::move(terms));
  RcsSystem& sys = points_->FormRcs(lambda);
  system_ = &sys;
  for (double c : costs) sys.cost += c;
  if (owners_add) return sys;
  for (const PoseRowTerm& t : terms) {
    const int32_t row = sys.layout.camera_row(t.image);
    if (row < 0) continue;  // a fixed camera: its cost only
    const int64_t o = sys.S.scalar_offset(row);
    AddPoseRowTerm(t, sys.S.block_size(row), sys.S.block_values(sys.S.diagonal_block(row)),
                   &sys.b[o], &sys.camera_side_gradient[o], &sys.camera_side_jtj_diagonal[o]);
  }
  return sys;
}

StepEvaluation PriorWorkers::EvaluateStep(double lambda, const std::vector<double>& delta_c,
                                          const std::vector<double>& candidate_cameras) {
  StepEvaluation e = points_->EvaluateStep(lambda, delta_c, candidate_cameras);
  e.model_cost += model_offset_;
  for (size_t x = 0; x < priors_.priors.size(); ++x) {
    const CameraCentrePrior& p = priors_.priors[x];
    Vec3 model = r_[x];
    const int32_t row = system_->layout.camera_row(p.image);
    if (row >= 0) {
      model += J_[x] * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(
                           delta_c.data() + system_->layout.row_offset(row));
    }
    e.model_cost += 0.5 * model.squaredNorm();
    const Vec3 r = CentrePriorResidual(
        candidate_cameras.data() + int64_t{camera_size_} * p.image, p, nullptr);
    e.candidate_cost += 0.5 * priors_.loss.Rho(r.squaredNorm());
  }
  return e;
}

}  // namespace dba
