// Point back-substitution and step evaluation (paper eq. 5); see
// back_substitute.h.
#include "dba/rcs/back_substitute.h"

#include <omp.h>

#include <algorithm>

#include "dba/camera/bal_camera_lanes.h"
#include "dba/camera/observation_residual.h"
#include "dba/common/memory.h"
#include "dba/common/progress.h"

namespace dba {
namespace {

// |r_a|² of the observations begin..begin+m of one point X at the
// candidate cameras, into squared[0..m); BAL four at a time.
void CandidateSquaredResiduals(const Problem& problem, const std::vector<double>& cameras,
                               RotationFrameCache* frames, int64_t begin, int m, const double* X,
                               std::vector<Vec2>* scratch, double* squared) {
  if (problem.model == CameraModel::kBal) {
    if (static_cast<int>(scratch->size()) < m) scratch->resize(m);
    BalPointResiduals(problem.obs_camera.data() + begin, problem.pixel(begin), cameras.data(),
                      frames, m, X, scratch->data(), nullptr, nullptr);
    for (int a = 0; a < m; ++a) squared[a] = (*scratch)[a].squaredNorm();
    return;
  }
  for (int a = 0; a < m; ++a) {
    const int64_t obs = begin + a;
    squared[a] = ObservationResidual(problem, cameras.data(), frames, problem.obs_camera[obs], X,
                                     problem.pixel(obs))
                     .squaredNorm();
  }
}

template <class Model>
StepEvaluation BackSubstituteWith(const Problem& problem, const UnknownLayout& layout,
                                  double lambda, const DampingBounds& bounds,
                                  const std::vector<double>& delta_c,
                                  const std::vector<double>& candidate_cameras,
                                  int num_threads, std::vector<double>* candidate_points,
                                  const RobustLoss& loss) {
  constexpr int kC = Model::kCamera;
  constexpr int kI = PointSystem<Model>::kI;
  using CameraVec = Eigen::Matrix<double, kC, 1>;
  using IntrinsicsVec = Eigen::Matrix<double, kI, 1>;
  // δ of an intrinsics row, padded with zeros to the packed Jacobian's width.
  auto intrinsics_delta = [&](int32_t row) {
    IntrinsicsVec d = IntrinsicsVec::Zero();
    const int64_t o = layout.row_offset(row);
    for (int j = 0; j < layout.block_size(row); ++j) d[j] = delta_c[o + j];
    return d;
  };
  double model_cost = 0.0, candidate_cost = 0.0, step_sq = 0.0;
  double squared = 0.0, inlier_squared = 0.0, inliers = 0.0;
  const int64_t num_points = problem.num_points();
  ProgressPhase progress("back-substitution");
  std::vector<PositionSpread> spreads(static_cast<size_t>(num_threads));
  const double first_share =
      std::max<double>(1.0, static_cast<double>((num_points + num_threads - 1) / num_threads));
#pragma omp parallel num_threads(num_threads) \
    reduction(+ : model_cost, candidate_cost, step_sq, squared, inlier_squared, inliers)
  {
    // The thread's own, written to `spreads` once at the end: neighbours in
    // that vector share a cache line (written per point, they took back-
    // substitution from 88 to 128 s at 1M).
    PositionSpread spread;
    PointSystem<Model> p;
    RotationFrameCache candidate_frames;
    std::vector<Vec2> candidate_r;
    std::vector<double> candidate_squared;
    const bool first_thread = omp_get_thread_num() == 0;
    // Static: each thread always sums the same points, so the costs (and
    // with them every LM decision) are the same from run to run.
#pragma omp for schedule(static)
    for (int64_t k = 0; k < num_points; ++k) {
      if (first_thread && (k & 4095) == 0) progress.Report(static_cast<double>(k) / first_share);
      LinearizePoint(problem, layout, loss, k, &p);
      InvertDampedV(lambda, bounds, &p);
      const int64_t begin = problem.point_offsets[k];
      // Model residuals start as r + Σ_e J_e δ_e (J_p δX is added below),
      // and rhs = -Σ_a J_pᵀ (r + Σ_e J_e δ_e) = -g_p - Σ_a Σ_e W_eᵀ δ_e.
      Vec3 rhs = Vec3::Zero();
      for (int a = 0; a < p.num_obs; ++a) {
        if (p.camera_row[a] >= 0) {
          const auto dc = Eigen::Map<const CameraVec>(delta_c.data() +
                                                      layout.row_offset(p.camera_row[a]));
          p.r[a].noalias() += p.J_c[a] * dc;
        }
        if constexpr (Model::kIntrinsics > 0) {
          if (p.intrinsics_row[a] >= 0) {
            p.r[a].noalias() += p.J_i[a] * intrinsics_delta(p.intrinsics_row[a]);
          }
        }
        rhs.noalias() -= p.J_p[a].transpose() * p.r[a];
      }
      const Eigen::Map<const Vec3> prior_w(p.prior != nullptr ? p.prior->weight : nullptr);
      if (p.prior != nullptr) rhs -= prior_w.cwiseProduct(p.prior_r);
      const Vec3 dX = p.V_inv * rhs;
      const Vec3 X = Eigen::Map<const Vec3>(problem.point(k));
      const Vec3 X_new = X + dX;
      Eigen::Map<Vec3>(candidate_points->data() + 3 * k) = X_new;
      step_sq += dX.squaredNorm();
      spread.Add(X);
      model_cost += p.model_offset;
      if (p.prior != nullptr) {
        model_cost += 0.5 * (p.prior_r + prior_w.cwiseProduct(dX)).squaredNorm();
        candidate_cost +=
            0.5 * prior_w.cwiseProduct(X_new - Eigen::Map<const Vec3>(p.prior->position)).squaredNorm();
      }
      if (static_cast<int>(candidate_squared.size()) < p.num_obs) {
        candidate_squared.resize(p.num_obs);
      }
      CandidateSquaredResiduals(problem, candidate_cameras, &candidate_frames, begin, p.num_obs,
                                X_new.data(), &candidate_r, candidate_squared.data());
      for (int a = 0; a < p.num_obs; ++a) {
        model_cost += 0.5 * (p.r[a] + p.J_p[a] * dX).squaredNorm();
        const double s = candidate_squared[a];
        candidate_cost += 0.5 * loss.Rho(s);
        squared += s;
        if (loss.IsInlier(s)) inlier_squared += s, inliers += 1.0;
      }
    }
    spreads[static_cast<size_t>(omp_get_thread_num())] = spread;
  }
  StepEvaluation e;
  e.model_cost = model_cost;
  e.candidate_cost = candidate_cost;
  e.candidate_residuals = {squared, inlier_squared, inliers};
  e.point_step_squared_norm = step_sq;
  // In thread order: the same sum from run to run.
  for (const PositionSpread& part : spreads) e.point_spread.Merge(part);
  return e;
}

}  // namespace

StepEvaluation BackSubstitute(const Problem& problem, const UnknownLayout& layout,
                              double lambda, const DampingBounds& bounds,
                              const std::vector<double>& delta_c,
                              const std::vector<double>& candidate_cameras, int num_threads,
                              std::vector<double>* candidate_points, const RobustLoss& loss) {
  if (candidate_points->size() != problem.points.size()) {
    AssignZeros(candidate_points, problem.points.size());
  }
  if (problem.model == CameraModel::kBal) {
    return BackSubstituteWith<BalModel>(problem, layout, lambda, bounds, delta_c,
                                        candidate_cameras, num_threads, candidate_points, loss);
  }
  return WithPhotoModel(layout.max_intrinsics_block(), [&]<class Model>() {
    return BackSubstituteWith<Model>(problem, layout, lambda, bounds, delta_c, candidate_cameras,
                                     num_threads, candidate_points, loss);
  });
}

}  // namespace dba
