// The residual of one observation in either camera model of a problem
// (problem/problem.h): BalResidual for kBal, PhotoResidual with the
// image's intrinsic group for kPhoto.
//
// Thread safety: pure function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dba/camera/bal_camera.h"
#include "dba/camera/rotation_frame_cache.h"
#include "dba/problem/problem.h"

namespace dba {

// r = project(camera i, X) - pixel, with the camera-side parameters taken
// from `cameras` (laid out as side.cameras; e.g. a candidate step) and the
// model and image groups from `side`.
Vec2 ObservationResidual(const CameraSide& side, const double* cameras, int32_t i,
                         const double* X, const double* pixel);
// The same with image i's rotation taken from `frames`, which must hold
// frames of `cameras` only (the trigonometry once per image, not per
// observation).
Vec2 ObservationResidual(const CameraSide& side, const double* cameras, RotationFrameCache* frames,
                         int32_t i, const double* X, const double* pixel);

// One pass over the observations at the problem's current parameters:
// those whose squared residual is not finite (a point at a camera centre, an
// overflowing value) — how many, and the first `keep` with their camera and
// point — and those whose point is behind its camera (camera-frame depth
// z <= 0; z >= 0 for a BAL camera, which looks down -z; EQUIRECTANGULAR sees
// every direction and is left out). COLMAP drops the latter before
// adjusting; dba counts them (the report's observations_behind_cameras).
struct ResidualScan {
  int64_t non_finite = 0;
  struct Where {
    int64_t observation, point;
    int32_t camera;
  };
  std::vector<Where> first_non_finite;
  int64_t behind_cameras = 0;
};
// `order` (empty: the problem's own): the order to walk the points in (a
// walk's: the cameras of consecutive points then stay in cache); the finds
// kept are the first `keep` in observation order all the same.
ResidualScan ScanResiduals(const Problem& problem, std::span<const int64_t> order = {}, int keep = 5);

}  // namespace dba
