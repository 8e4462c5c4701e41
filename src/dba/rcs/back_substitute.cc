// Point back-substitution and step evaluation (paper eq. 5); see
// back_substitute.h.
#include "dba/rcs/back_substitute.h"

#include <omp.h>

namespace dba {

StepEvaluation BackSubstitute(const BalProblem& problem, double lambda,
                              const DampingBounds& bounds,
                              const std::vector<double>& delta_c,
                              const std::vector<double>& candidate_cameras,
                              int num_threads,
                              std::vector<double>* candidate_points) {
  candidate_points->resize(problem.points.size());
  double model_cost = 0.0, candidate_cost = 0.0, step_sq = 0.0, x_sq = 0.0;
  const int64_t num_points = problem.num_points();
#pragma omp parallel num_threads(num_threads) \
    reduction(+ : model_cost, candidate_cost, step_sq, x_sq)
  {
    PointSystem p;
#pragma omp for schedule(dynamic, 256)
    for (int64_t k = 0; k < num_points; ++k) {
      LinearizePoint(problem, k, &p);
      EliminatePoint(lambda, bounds, &p);
      const int64_t begin = problem.point_offsets[k];
      Vec3 rhs = -p.g_p;
      for (int a = 0; a < p.num_obs; ++a) {
        const int64_t ca = problem.obs_camera[begin + a];
        rhs.noalias() -= p.W[a].transpose() *
                         Eigen::Map<const Vec9>(delta_c.data() + 9 * ca);
      }
      const Vec3 dX = p.V_inv * rhs;
      const Vec3 X = Eigen::Map<const Vec3>(problem.point(k));
      const Vec3 X_new = X + dX;
      Eigen::Map<Vec3>(candidate_points->data() + 3 * k) = X_new;
      step_sq += dX.squaredNorm();
      x_sq += X.squaredNorm();
      for (int a = 0; a < p.num_obs; ++a) {
        const int64_t obs = begin + a;
        const int64_t ca = problem.obs_camera[obs];
        const Vec2 model = p.r[a] +
                           p.J_c[a] * Eigen::Map<const Vec9>(delta_c.data() + 9 * ca) +
                           p.J_p[a] * dX;
        model_cost += 0.5 * model.squaredNorm();
        const Vec2 r_new = BalResidual(candidate_cameras.data() + 9 * ca,
                                       X_new.data(), problem.pixel(obs));
        candidate_cost += 0.5 * r_new.squaredNorm();
      }
    }
  }
  StepEvaluation e;
  e.model_cost = model_cost;
  e.candidate_cost = candidate_cost;
  e.point_step_squared_norm = step_sq;
  e.point_squared_norm = x_sq;
  return e;
}

}  // namespace dba
