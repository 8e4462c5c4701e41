// Per-point linearization and elimination; see eliminate_point.h.
#include "dba/rcs/eliminate_point.h"

#include <Eigen/LU>

namespace dba {

void LinearizePoint(const BalProblem& problem, int64_t k, PointSystem* sys) {
  const int64_t begin = problem.point_offsets[k];
  const int m = static_cast<int>(problem.point_offsets[k + 1] - begin);
  sys->num_obs = m;
  if (static_cast<int>(sys->J_c.size()) < m) {
    sys->J_c.resize(m);
    sys->J_p.resize(m);
    sys->r.resize(m);
    sys->W.resize(m);
    sys->T.resize(m);
  }
  const double* X = problem.point(k);
  sys->V.setZero();
  sys->g_p.setZero();
  sys->cost = 0.0;
  for (int a = 0; a < m; ++a) {
    const int64_t obs = begin + a;
    sys->r[a] = BalResidualAndJacobians(problem.camera(problem.obs_camera[obs]),
                                        X, problem.pixel(obs), &sys->J_c[a],
                                        &sys->J_p[a]);
    sys->cost += 0.5 * sys->r[a].squaredNorm();
    sys->V.noalias() += sys->J_p[a].transpose() * sys->J_p[a];
    sys->g_p.noalias() += sys->J_p[a].transpose() * sys->r[a];
    sys->W[a].noalias() = sys->J_c[a].transpose() * sys->J_p[a];
  }
}

void EliminatePoint(double lambda, const DampingBounds& bounds,
                    PointSystem* sys) {
  Eigen::Matrix3d V_damped = sys->V;
  for (int d = 0; d < 3; ++d) V_damped(d, d) += lambda * bounds.Clamp(sys->V(d, d));
  sys->V_inv = V_damped.inverse();
  for (int a = 0; a < sys->num_obs; ++a) {
    sys->T[a].noalias() = sys->W[a] * sys->V_inv;
  }
}

}  // namespace dba
