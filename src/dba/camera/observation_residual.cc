// One observation's residual in either camera model; see observation_residual.h.
#include "dba/camera/observation_residual.h"

#include "dba/camera/photo_camera.h"

#include <omp.h>

#include <algorithm>
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

// With camera i's rotation frame given.
static Vec2 ResidualInFrame(const CameraSide& side, const double* cameras, const RotationFrame& frame,
                            int32_t i, const double* X, const double* pixel) {
  if (side.model == CameraModel::kBal) {
    return BalResidualAndJacobians(frame, cameras + kBalCameraSize * int64_t{i}, X, pixel, nullptr,
                                   nullptr);
  }
  const double* pose = cameras + kPhotoPoseSize * int64_t{i};
  const int32_t g = side.camera_intrinsics[i];
  return PhotoResidualAndJacobians(side.group_model(g), frame, pose,
                                   cameras + side.intrinsics_offset(g), X, pixel, nullptr,
                                   nullptr, nullptr);
}

Vec2 ObservationResidual(const CameraSide& side, const double* cameras, RotationFrameCache* frames,
                         int32_t i, const double* X, const double* pixel) {
  const double* camera = cameras + int64_t{side.camera_size()} * i;
  return ResidualInFrame(side, cameras, frames->Get(i, camera), i, X, pixel);
}

namespace {

// Whether a point at camera-frame depth z is behind the camera: z <= 0 in the
// photogrammetric model, z >= 0 for a BAL camera (it looks down -z);
// EQUIRECTANGULAR sees every direction.
bool Behind(const CameraSide& side, int32_t i, double z) {
  if (side.model == CameraModel::kBal) return z >= 0;
  if (side.group_model(side.camera_intrinsics[i]) == LensModel::kEquirectangular) return false;
  return z <= 0;
}

// `where` into `first` (the `keep` smallest observations, in order).
void KeepFirst(const ResidualScan::Where& where, int keep, std::vector<ResidualScan::Where>* first) {
  const auto at = std::lower_bound(
      first->begin(), first->end(), where,
      [](const ResidualScan::Where& a, const ResidualScan::Where& b) { return a.observation < b.observation; });
  if (at - first->begin() >= keep) return;
  first->insert(at, where);
  if (static_cast<int>(first->size()) > keep) first->pop_back();
}

}  // namespace

ResidualScan ScanResiduals(const Problem& problem, std::span<const int64_t> order, int keep) {
  // Every camera's frame first (the trigonometry once per camera: in an
  // input whose observations come in no camera order a cache would miss on
  // most of them; 144 bytes per camera while the scan runs).
  std::vector<RotationFrame> frames(static_cast<size_t>(problem.num_images()));
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < problem.num_images(); ++i) frames[i] = MakeRotationFrame(problem.camera(i));
  // Each thread a contiguous range of the walk, keeping the first `keep`
  // finds in observation order.
  std::vector<ResidualScan> parts(static_cast<size_t>(omp_get_max_threads()));
#pragma omp parallel num_threads(static_cast<int>(parts.size()))
  {
    ResidualScan& scan = parts[static_cast<size_t>(omp_get_thread_num())];
#pragma omp for schedule(static)
    for (int64_t at = 0; at < problem.num_points(); ++at) {
      const int64_t k = order.empty() ? at : order[at];
      const Vec3 X(problem.point(k)[0], problem.point(k)[1], problem.point(k)[2]);
      for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
        const int32_t i = problem.obs_camera[o];
        const double z = frames[i].R.row(2).dot(X) + problem.camera(i)[5];
        scan.behind_cameras += Behind(problem, i, z);
        if (std::isfinite(ResidualInFrame(problem, problem.cameras.data(), frames[i], i,
                                          problem.point(k), problem.pixel(o))
                              .squaredNorm())) {
          continue;
        }
        KeepFirst({o, k, i}, keep, &scan.first_non_finite);
        ++scan.non_finite;
      }
    }
  }
  ResidualScan all;
  for (const ResidualScan& part : parts) {
    all.non_finite += part.non_finite;
    all.behind_cameras += part.behind_cameras;
    for (const auto& where : part.first_non_finite) KeepFirst(where, keep, &all.first_non_finite);
  }
  return all;
}

}  // namespace dba
