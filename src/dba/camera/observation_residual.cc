// One observation's residual in either camera model; see observation_residual.h.
#include "dba/camera/observation_residual.h"

#include "dba/camera/photo_camera.h"

#include <omp.h>

#include <cmath>
#include <vector>

namespace dba {

Vec2 ObservationResidual(const CameraSide& side, const double* cameras, int32_t i,
                         const double* X, const double* pixel) {
  if (side.model == CameraModel::kBal) {
    return BalResidual(cameras + kBalCameraSize * int64_t{i}, X, pixel);
  }
  const int32_t g = side.camera_intrinsics[i];
  return PhotoResidual(side.group_model(g), cameras + kPhotoPoseSize * int64_t{i},
                       cameras + side.intrinsics_offset(g), X, pixel);
}

Vec2 ObservationResidual(const CameraSide& side, const double* cameras, RotationFrameCache* frames,
                         int32_t i, const double* X, const double* pixel) {
  if (side.model == CameraModel::kBal) {
    const double* camera = cameras + kBalCameraSize * int64_t{i};
    return BalResidualAndJacobians(frames->Get(i, camera), camera, X, pixel, nullptr, nullptr);
  }
  const double* pose = cameras + kPhotoPoseSize * int64_t{i};
  const int32_t g = side.camera_intrinsics[i];
  return PhotoResidualAndJacobians(side.group_model(g), frames->Get(i, pose), pose,
                                   cameras + side.intrinsics_offset(g), X, pixel, nullptr,
                                   nullptr, nullptr);
}

int64_t CountBehindCameras(const Problem& problem) {
  const bool bal = problem.model == CameraModel::kBal;
  const int64_t n = problem.num_images();
  std::vector<Mat3> R(static_cast<size_t>(n));
  std::vector<uint8_t> sees_all(static_cast<size_t>(n), 0);
  for (int64_t i = 0; i < n; ++i) {
    const double* c = problem.camera(i);
    R[i] = AngleAxisToRotation(Vec3(c[0], c[1], c[2]));
    sees_all[i] = !bal && problem.group_model(problem.camera_intrinsics[i]) == LensModel::kEquirectangular;
  }
  int64_t behind = 0;
#pragma omp parallel for schedule(static) reduction(+ : behind)
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    const Vec3 X(problem.point(k)[0], problem.point(k)[1], problem.point(k)[2]);
    for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
      const int32_t i = problem.obs_camera[o];
      if (sees_all[i]) continue;
      const double z = R[i].row(2).dot(X) + problem.camera(i)[5];
      behind += bal ? z >= 0 : z <= 0;
    }
  }
  return behind;
}

NonFiniteResiduals FindNonFiniteResiduals(const Problem& problem, int keep) {
  // Each thread a contiguous range of points, its finds appended in thread
  // order: the first `keep` are the first in observation order.
  std::vector<NonFiniteResiduals> parts(static_cast<size_t>(omp_get_max_threads()));
#pragma omp parallel num_threads(static_cast<int>(parts.size()))
  {
    NonFiniteResiduals& bad = parts[static_cast<size_t>(omp_get_thread_num())];
    RotationFrameCache frames;  // the trigonometry once per camera, not per observation
#pragma omp for schedule(static)
    for (int64_t k = 0; k < problem.num_points(); ++k) {
      for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
        const int32_t i = problem.obs_camera[o];
        if (std::isfinite(ObservationResidual(problem, problem.cameras.data(), &frames, i,
                                              problem.point(k), problem.pixel(o))
                              .squaredNorm())) {
          continue;
        }
        if (static_cast<int>(bad.first.size()) < keep) bad.first.push_back({o, k, i});
        ++bad.count;
      }
    }
  }
  NonFiniteResiduals all;
  for (const NonFiniteResiduals& part : parts) {
    all.count += part.count;
    for (const auto& where : part.first) {
      if (static_cast<int>(all.first.size()) < keep) all.first.push_back(where);
    }
  }
  return all;
}

}  // namespace dba
