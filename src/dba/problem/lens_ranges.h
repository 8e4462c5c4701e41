// The physical range of each lens model's parameters (lens_model.h): what
// no real camera has is refused at the input, before it can give a solve
// that ends with exit 0 and means nothing (a focal length of 0 projects
// every point onto the principal point; the cost never changes).
//
//   every parameter           finite
//   f, fx, fy                 > 0
//   FOV's omega               |ω| < π (tan(ω/2) is the lens's field)
//   EUCM's alpha, beta        0 ≤ α ≤ 1, β > 0
//   EQUIRECTANGULAR's w, h    ≥ 1 (the panorama's size in pixels)
//
// Thread safety: pure functions.
#pragma once

#include <string>

#include "dba/problem/lens_model.h"

namespace dba {

// Why `params` (LensModelParams(m) of them) are no camera's: e.g. "fx is
// -3: a focal length must be > 0"; empty when they are in range.
std::string LensValueOutOfRange(LensModel m, const double* params);

}  // namespace dba
