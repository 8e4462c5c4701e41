// The residual of one observation in either camera model of a problem
// (problem/bal_problem.h): BalResidual for kBal, PhotoResidual with the
// image's intrinsic group for kPhoto.
//
// Thread safety: pure function.
#pragma once

#include <cstdint>

#include "dba/camera/bal_camera.h"
#include "dba/problem/bal_problem.h"

namespace dba {

// r = project(camera i, X) - pixel, with the camera-side parameters taken
// from `cameras` (laid out as side.cameras; e.g. a candidate step) and the
// model and image groups from `side`.
Vec2 ObservationResidual(const BalProblem& side, const double* cameras, int32_t i,
                         const double* X, const double* pixel);

}  // namespace dba
