// Plausible lens parameters; see typical_lens.h.
#include "dba/camera/typical_lens.h"

namespace dba {

std::vector<double> TypicalLensParams(LensModel model, double focal, double width,
                                      double height) {
  const double f = focal, fy = 1.002 * focal;
  const double cx = 0.5 * width + 3.1, cy = 0.5 * height - 2.3;
  switch (model) {
    case LensModel::kSimplePinhole:
      return {f, cx, cy};
    case LensModel::kPinhole:
      return {f, fy, cx, cy};
    case LensModel::kSimpleRadial:
      return {f, cx, cy, -0.08};
    case LensModel::kRadial:
      return {f, cx, cy, -0.08, 0.015};
    case LensModel::kOpenCV:
      return {f, fy, cx, cy, -0.08, 0.015, 4e-4, -3e-4};
    case LensModel::kOpenCVFisheye:
      return {f, fy, cx, cy, 0.03, -0.01, 0.002, -5e-4};
    case LensModel::kFullOpenCV:
      return {f, fy, cx, cy, -0.08, 0.015, 4e-4, -3e-4, -0.002, 0.01, -0.003, 0.001};
    case LensModel::kFov:
      return {f, fy, cx, cy, 0.6};
    case LensModel::kSimpleRadialFisheye:
      return {f, cx, cy, 0.03};
    case LensModel::kRadialFisheye:
      return {f, cx, cy, 0.03, -0.01};
    case LensModel::kThinPrismFisheye:
      return {f, fy, cx, cy, 0.03, -0.01, 3e-4, -2e-4, 0.002, -5e-4, 2e-4, -1e-4};
    case LensModel::kRadTanThinPrismFisheye:
      return {f,      fy,    cx,    cy,   0.03,   -0.01, 0.002, -5e-4,
              1e-4,   -1e-5, 3e-4,  -2e-4, 2e-4,  -5e-5, -1e-4, 3e-5};
    case LensModel::kSimpleDivision:
      return {f, cx, cy, -0.05};
    case LensModel::kDivision:
      return {f, fy, cx, cy, -0.05};
    case LensModel::kSimpleFisheye:
      return {f, cx, cy};
    case LensModel::kFisheye:
      return {f, fy, cx, cy};
    case LensModel::kEucm:
      return {f, fy, cx, cy, 0.6, 1.1};
    case LensModel::kEquirectangular:
      return {width, height};
    case LensModel::kBrown:
      return {f, cx, cy, -0.08, 0.015, -0.002, 4e-4, -3e-4, 0.8, -0.3};
  }
  return {};
}

}  // namespace dba
