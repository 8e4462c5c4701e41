// Camera priors around the points' workers; see prior_workers.h.
#include "dba/lm/prior_workers.h"

#include <stdexcept>
#include <string>

namespace dba {

double CameraPriorsCost(const CameraPriors& priors, const CameraSide& side) {
  double cost = 0.0;
  for (const CameraCentrePrior& p : priors.priors) {
    const Vec3 r = CentrePriorResidual(side.cameras.data() + ExposurePoseOffset(side, p.image),
                                       priors.lever_arm, p, nullptr);
    cost += 0.5 * priors.loss.Rho(r.squaredNorm());
  }
  return cost;
}

PriorWorkers::PriorWorkers(PointWorkers* points, const std::vector<double>* x,
                           const CameraSide& side, const CameraPriors& priors)
    : points_(points), x_(x), priors_(priors) {
  for (const CameraCentrePrior& p : priors.priors) {
    pose_offset_.push_back(ExposurePoseOffset(side, p.image));
  }
  if (priors.refine_lever_arm) lever_offset_ = static_cast<int64_t>(side.cameras.size());
}

Vec3 PriorWorkers::LeverArm(const std::vector<double>& x) const {
  return lever_offset_ < 0 ? priors_.lever_arm : Vec3(x.data() + lever_offset_);
}

RcsSystem& PriorWorkers::FormRcs(double lambda) {
  const size_t n = priors_.priors.size();
  r_.resize(n);
  J_.resize(n);
  std::vector<double> costs(n);
  std::vector<PoseRowTerm> terms(n);
  model_offset_ = 0.0;
  const Vec3 a = LeverArm(*x_);
  for (size_t x = 0; x < n; ++x) {
    const CameraCentrePrior& p = priors_.priors[x];
    CentrePriorJacobian J_pose;
    LeverArmJacobian J_a;
    Vec3 r = CentrePriorResidual(x_->data() + pose_offset_[x], a, p, &J_pose, &J_a);
    J_[x] << J_pose, J_a;
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
    const auto J_c = J_[x].leftCols<6>();
    terms[x].image = p.image;
    terms[x].JtJ = J_c.transpose() * J_c;
    terms[x].g = J_c.transpose() * r;
  }
  // The RCS spread over ranks: its rows' owners add the terms as they sum
  // the rows; else they go into the system here.
  const bool owners_add = points_->TakesPoseTerms();
  if (owners_add) points_->SetPoseTerms(std::move(terms));
  RcsSystem& sys = points_->FormRcs(lambda);
  system_ = &sys;
  for (double c : costs) sys.cost += c;
  if (owners_add) {
    if (lever_offset_ >= 0) {
      throw std::logic_error("PriorWorkers: a refined lever arm in an RCS spread over ranks");
    }
    return sys;
  }
  for (const PoseRowTerm& t : terms) {
    const int32_t row = sys.layout.camera_row(t.image);
    if (row < 0) continue;  // a fixed camera: its cost only
    const int64_t o = sys.S.scalar_offset(row);
    AddPoseRowTerm(t, sys.S.block_size(row), sys.S.block_values(sys.S.diagonal_block(row)),
                   &sys.b[o], &sys.camera_side_gradient[o], &sys.camera_side_jtj_diagonal[o]);
  }
  if (lever_offset_ >= 0) AddLeverArmTerms(&sys);
  return sys;
}

// S_aa += J̃_aᵀ J̃_a, S_ca += J̃_cᵀ J̃_a, b_a -= J̃_aᵀ r̃ (gradient, diagonal).
void PriorWorkers::AddLeverArmTerms(RcsSystem* sys) const {
  const int32_t lever = sys->layout.lever_arm_row();
  const int64_t o = sys->S.scalar_offset(lever);
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> S_aa(
      sys->S.block_values(sys->S.diagonal_block(lever)));
  for (size_t x = 0; x < J_.size(); ++x) {
    const auto J_a = J_[x].rightCols<3>();
    S_aa += J_a.transpose() * J_a;
    const Vec3 g = J_a.transpose() * r_[x];
    for (int k = 0; k < 3; ++k) {
      sys->b[o + k] -= g[k];
      sys->camera_side_gradient[o + k] += g[k];
      sys->camera_side_jtj_diagonal[o + k] += J_a.col(k).squaredNorm();
    }
    const int32_t row = sys->layout.camera_row(priors_.priors[x].image);
    if (row < 0) continue;
    const int64_t block = sys->S.FindBlock(row, lever);
    if (block < 0) {  // rcs/rcs_pattern.cc gives every camera row one
      throw std::logic_error("lever-arm terms: the RCS has no block at camera row " +
                             std::to_string(row) + ", lever-arm row " + std::to_string(lever));
    }
    Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>>(sys->S.block_values(block)) +=
        J_[x].leftCols<6>().transpose() * J_a;
  }
}

StepEvaluation PriorWorkers::EvaluateStep(double lambda, const std::vector<double>& delta_c) {
  // The points' workers step the camera side alone; the priors see x ⊞ δ.
  candidate_.resize(x_->size());
  system_->layout.Plus(x_->data(), delta_c.data(), candidate_.data());
  const std::vector<double>& candidate_x = candidate_;
  StepEvaluation e = points_->EvaluateStep(lambda, delta_c);
  e.model_cost += model_offset_;
  const Vec3 a = LeverArm(candidate_x);
  const int32_t lever = system_->layout.lever_arm_row();
  for (size_t x = 0; x < priors_.priors.size(); ++x) {
    const CameraCentrePrior& p = priors_.priors[x];
    Vec3 model = r_[x];
    const int32_t row = system_->layout.camera_row(p.image);
    if (row >= 0) {
      model += J_[x].leftCols<6>() * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(
                                         delta_c.data() + system_->layout.row_offset(row));
    }
    if (lever >= 0) {
      model += J_[x].rightCols<3>() * Vec3(delta_c.data() + system_->layout.row_offset(lever));
    }
    e.model_cost += 0.5 * model.squaredNorm();
    const Vec3 r = CentrePriorResidual(candidate_x.data() + pose_offset_[x], a, p, nullptr);
    e.candidate_cost += 0.5 * priors_.loss.Rho(r.squaredNorm());
  }
  return e;
}

}  // namespace dba
