// Per-point linearization and elimination; see eliminate_point.h.
#include "dba/rcs/eliminate_point.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "dba/camera/bal_camera_lanes.h"
#include "dba/camera/rig_pose.h"

namespace dba {
namespace {

template <class Model>
void Resize(int m, PointSystem<Model>* sys) {
  if (static_cast<int>(sys->J_c.size()) >= m) return;
  sys->camera_row.resize(m);
  sys->intrinsics_row.resize(m);
  sys->J_c.resize(m);
  sys->J_i.resize(m);
  sys->J_p.resize(m);
  sys->r.resize(m);
  sys->K.resize(m);
  sys->W_i.resize(m);
}

// An observation's Jacobians in its frame's and its sensor's steps (rigs,
// camera/rig_pose.h), from its image's point Jacobian J_p.
template <class Model>
void RigJacobians(const Problem& problem, int32_t i, const RotationFrame& image, const double* X,
                  int a, PoseJacobian* J_sensor, PointSystem<Model>* sys) {
  const int32_t f = problem.image_frame[i];
  const int32_t g = problem.camera_intrinsics[i];
  const double* frame_pose = problem.cameras.data() + problem.frame_offset(f);
  const double* sensor_pose = problem.cameras.data() + problem.sensor_offset(g);
  // Frames, then groups, in one cache (a copy: the second Get may take the
  // first's slot).
  const RotationFrame frame = sys->rig_frames.Get(f, frame_pose);
  const RotationFrame& sensor =
      sys->rig_frames.Get(static_cast<int32_t>(problem.num_frames() + g), sensor_pose);
  const RigChain chain = MakeRigChain(frame, sensor, sensor_pose);
  const double* pose = problem.camera(i);
  const Vec3 P = image.R * Eigen::Map<const Vec3>(X) + Vec3(pose[3], pose[4], pose[5]);
  RigResidualJacobians(chain, image.R, P, sys->J_p[a], &sys->J_c[a], J_sensor);
}

// Residual and Jacobians of one observation in the photogrammetric model;
// the intrinsics Jacobian packed to the group's free parameters (and, on a
// rig, its sensor pose's six after them).
template <class Model>
Vec2 LinearizePhotoObservation(const Problem& problem, const UnknownLayout& layout, int64_t obs,
                               const double* X, int a, PointSystem<Model>* sys) {
  const int32_t i = problem.obs_camera[obs];
  const int32_t g = problem.camera_intrinsics[i];
  const auto rows = layout.rows_of_image(problem, i);
  sys->camera_row[a] = rows.camera;
  const int32_t row = sys->intrinsics_row[a] = rows.intrinsics;
  IntrinsicsJacobian full;
  const RotationFrame& image = sys->frames.Get(i, problem.camera(i));
  const bool rig = problem.has_rigs();
  const Vec2 r = PhotoResidualAndJacobians(
      problem.group_model(g), image, problem.camera(i), problem.intrinsics(g), X,
      problem.pixel(obs), rig ? nullptr : &sys->J_c[a], row >= 0 ? &full : nullptr, &sys->J_p[a]);
  PoseJacobian J_sensor;
  const int n = row >= 0 ? layout.intrinsic_unknowns(row) : 0;
  const bool sensor = row >= 0 && n < layout.block_size(row);
  if (rig) RigJacobians(problem, i, image, X, a, sensor ? &J_sensor : nullptr, sys);
  if (row >= 0) {
    const auto& index = layout.intrinsics_free_index(g);
    auto& J = sys->J_i[a];
    for (int j = 0; j < n; ++j) J.col(j) = full.col(index[j]);
    int j = n;
    if (sensor) {
      for (; j < n + kPoseSize; ++j) J.col(j) = J_sensor.col(j - n);
    }
    for (; j < Model::kIntrinsics; ++j) J.col(j).setZero();
  }
  return r;
}

// Residuals and Jacobians of a BAL point's m observations, four at a time
// (camera/bal_camera_lanes.h).
template <class Model>
void LinearizeBalObservations(const Problem& problem, const UnknownLayout& layout, int64_t begin,
                              int m, const double* X, PointSystem<Model>* sys) {
  const int32_t* cameras = problem.obs_camera.data() + begin;
  for (int a = 0; a < m; ++a) sys->camera_row[a] = layout.camera_row(cameras[a]);
  std::fill_n(sys->intrinsics_row.begin(), m, -1);
  BalPointResiduals(cameras, problem.pixel(begin), problem.cameras.data(), &sys->frames, m, X,
                    sys->r.data(), sys->J_c.data(), sys->J_p.data());
}

}  // namespace

template <class Model>
void LinearizePoint(const Problem& problem, const UnknownLayout& layout,
                    const RobustLoss& loss, int64_t k, PointSystem<Model>* sys) {
  const int64_t begin = problem.point_offsets[k];
  const int m = static_cast<int>(problem.point_offsets[k + 1] - begin);
  sys->num_obs = m;
  Resize(m, sys);
  const double* X = problem.point(k);
  if constexpr (Model::kIntrinsics == 0) {
    LinearizeBalObservations(problem, layout, begin, m, X, sys);
  } else {
    for (int a = 0; a < m; ++a) {
      sys->r[a] = LinearizePhotoObservation(problem, layout, begin + a, X, a, sys);
    }
  }
  // Costs first (correcting r and J for a robust loss), then V and g_p from
  // the corrected values in a loop of their own: together, the sums did
  // not fit the registers and went through the stack in mixed widths.
  double cost = 0.0, model_offset = 0.0;
  ResidualSums residuals;
  if (loss.trivial()) {
    for (int a = 0; a < m; ++a) residuals.squared += sys->r[a].squaredNorm();
    residuals.inlier_squared = residuals.squared;
    residuals.inliers = m;
    cost = 0.5 * residuals.squared;
  } else {
    for (int a = 0; a < m; ++a) {
      const double s = sys->r[a].squaredNorm();
      residuals.Add(s, loss.IsInlier(s));
      double rho[3];
      loss.Evaluate(s, rho);
      const LossCorrection correction(s, rho);
      const Vec2 r = sys->r[a];
      correction.CorrectJacobian(r, &sys->J_p[a]);
      if (sys->camera_row[a] >= 0) correction.CorrectJacobian(r, &sys->J_c[a]);
      if (sys->intrinsics_row[a] >= 0) correction.CorrectJacobian(r, &sys->J_i[a]);
      sys->r[a] = correction.Residual(r);
      cost += 0.5 * rho[0];
      model_offset += 0.5 * (rho[0] - sys->r[a].squaredNorm());
    }
  }
  // V = Σ J_pᵀ J_p (lower triangle, mirrored), g_p = Σ J_pᵀ r, in locals.
  double v00 = 0, v10 = 0, v11 = 0, v20 = 0, v21 = 0, v22 = 0, g0 = 0, g1 = 0, g2 = 0;
  for (int a = 0; a < m; ++a) {
    const double* J = sys->J_p[a].data();  // row-major 2x3
    const double r0 = sys->r[a][0], r1 = sys->r[a][1];
    v00 += J[0] * J[0] + J[3] * J[3];
    v10 += J[1] * J[0] + J[4] * J[3];
    v11 += J[1] * J[1] + J[4] * J[4];
    v20 += J[2] * J[0] + J[5] * J[3];
    v21 += J[2] * J[1] + J[5] * J[4];
    v22 += J[2] * J[2] + J[5] * J[5];
    g0 += J[0] * r0 + J[3] * r1;
    g1 += J[1] * r0 + J[4] * r1;
    g2 += J[2] * r0 + J[5] * r1;
  }
  sys->V << v00, v10, v20, v10, v11, v21, v20, v21, v22;
  sys->g_p = Vec3(g0, g1, g2);
  sys->cost = cost;
  sys->model_offset = model_offset;
  sys->residuals = residuals;
  sys->prior = problem.point_prior(k);
  if (sys->prior != nullptr) {
    const Eigen::Map<const Vec3> w(sys->prior->weight);
    sys->prior_r = w.cwiseProduct(Eigen::Map<const Vec3>(X) -
                                  Eigen::Map<const Vec3>(sys->prior->position));
    sys->V.diagonal() += w.cwiseAbs2();
    sys->g_p += w.cwiseProduct(sys->prior_r);
    sys->cost += 0.5 * sys->prior_r.squaredNorm();
  }
}

// V_λ⁻¹ of the symmetric V_λ = V + λ clamp(diag V) by cofactors, in
// scalars: Eigen's 3x3 inverse stored V_λ to the stack element by element
// and read it back as vectors (failed store forwards, most of its time).
bool PointDetermined(const Eigen::Matrix3d& V) {
  const Vec3 values = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(V).eigenvalues();
  return values[0] > 1e-12 * values[2];
}

Eigen::Matrix3d GeneralizedInverse(const Eigen::Matrix3d& V) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(V);
  const Vec3& values = eigen.eigenvalues();
  Vec3 inverted = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    if (values[a] > 1e-12 * values[2]) inverted[a] = 1.0 / values[a];
  }
  return eigen.eigenvectors() * inverted.asDiagonal() * eigen.eigenvectors().transpose();
}

template <class Model>
void InvertDampedV(double lambda, const DampingBounds& bounds, PointSystem<Model>* sys) {
  const Eigen::Matrix3d& V = sys->V;
  const double v00 = V(0, 0) + lambda * bounds.Clamp(V(0, 0));
  const double v11 = V(1, 1) + lambda * bounds.Clamp(V(1, 1));
  const double v22 = V(2, 2) + lambda * bounds.Clamp(V(2, 2));
  const double v10 = V(1, 0), v20 = V(2, 0), v21 = V(2, 1);
  const double c00 = v11 * v22 - v21 * v21, c10 = v20 * v21 - v10 * v22,
               c20 = v10 * v21 - v11 * v20;
  const double inv_det = 1.0 / (v00 * c00 + v10 * c10 + v20 * c20);
  const double i00 = c00 * inv_det, i10 = c10 * inv_det, i20 = c20 * inv_det;
  const double i11 = (v00 * v22 - v20 * v20) * inv_det;
  const double i21 = (v10 * v20 - v00 * v21) * inv_det;
  const double i22 = (v00 * v11 - v10 * v10) * inv_det;
  sys->V_inv << i00, i10, i20, i10, i11, i21, i20, i21, i22;
  // Undamped (the analyse stage: LM's λ is never 0), a V singular or
  // nearly has V⁺ instead, decided by its eigenvalues.
  if (lambda == 0.0 && !(inv_det > 0 && 1.0 / inv_det > 1e-12 * v00 * v11 * v22)) {
    sys->V_inv = GeneralizedInverse(V);
  }
}

template <class Model>
void EliminatePoint(double lambda, const DampingBounds& bounds, PointSystem<Model>* sys) {
  InvertDampedV(lambda, bounds, sys);
  const Eigen::Matrix3d& Vi = sys->V_inv;  // symmetric
  const double i00 = Vi(0, 0), i10 = Vi(1, 0), i20 = Vi(2, 0), i11 = Vi(1, 1), i21 = Vi(2, 1),
               i22 = Vi(2, 2);
  for (int a = 0; a < sys->num_obs; ++a) {
    // K_a = J_p,a V_λ⁻¹, row by row, in scalars (as V above).
    const double* J = sys->J_p[a].data();  // row-major 2x3
    double* K = sys->K[a].data();
    for (int row = 0; row < 2; ++row) {
      const double j0 = J[3 * row], j1 = J[3 * row + 1], j2 = J[3 * row + 2];
      K[3 * row] = j0 * i00 + j1 * i10 + j2 * i20;
      K[3 * row + 1] = j0 * i10 + j1 * i11 + j2 * i21;
      K[3 * row + 2] = j0 * i20 + j1 * i21 + j2 * i22;
    }
    if constexpr (Model::kIntrinsics == 0) continue;
    if (sys->intrinsics_row[a] >= 0) {
      sys->W_i[a].noalias() = sys->J_i[a].transpose() * sys->J_p[a];
    }
  }
}

#define DBA_INSTANTIATE(Model)                                                              \
  template void LinearizePoint(const Problem&, const UnknownLayout&, const RobustLoss&, int64_t, \
                               PointSystem<Model>*);                                            \
  template void InvertDampedV(double, const DampingBounds&, PointSystem<Model>*);               \
  template void EliminatePoint(double, const DampingBounds&, PointSystem<Model>*);
DBA_INSTANTIATE(BalModel)
DBA_INSTANTIATE(PhotoModelOf<5>)
DBA_INSTANTIATE(PhotoModelOf<8>)
DBA_INSTANTIATE(PhotoModelOf<12>)
DBA_INSTANTIATE(PhotoModelOf<16>)
#undef DBA_INSTANTIATE

}  // namespace dba
