// One observation's residual in either camera model; see observation_residual.h.
#include "dba/camera/observation_residual.h"

#include "dba/camera/photo_camera.h"

namespace dba {

Vec2 ObservationResidual(const BalProblem& side, const double* cameras, int32_t i,
                         const double* X, const double* pixel) {
  if (side.model == CameraModel::kBal) {
    return BalResidual(cameras + kBalCameraSize * int64_t{i}, X, pixel);
  }
  const int64_t intrinsics = kPhotoPoseSize * side.num_cameras();
  return PhotoResidual(cameras + kPhotoPoseSize * int64_t{i},
                       cameras + intrinsics + kPhotoIntrinsicsSize * int64_t{side.camera_intrinsics[i]},
                       X, pixel);
}

}  // namespace dba
