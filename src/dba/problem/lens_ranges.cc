// The lens parameters' physical ranges; see lens_ranges.h.
#include "dba/problem/lens_ranges.h"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace dba {
namespace {

std::string Value(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

// The rule parameter `name` of model `m` breaks at value v; empty if none.
std::string RuleBroken(LensModel m, const std::string& name, double v) {
  if (!std::isfinite(v)) return "is not finite";
  if ((name == "f" || name == "fx" || name == "fy") && !(v > 0)) {
    return "must be > 0 (a focal length)";
  }
  if (m == LensModel::kFov && name == "omega" && !(std::abs(v) < std::numbers::pi)) {
    return "must be within (-pi, pi) (the lens's field of view, radians)";
  }
  if (m == LensModel::kEucm && name == "alpha" && !(v >= 0 && v <= 1)) {
    return "must be within [0, 1]";
  }
  if (m == LensModel::kEucm && name == "beta" && !(v > 0)) return "must be > 0";
  if (m == LensModel::kEquirectangular && !(v >= 1)) {
    return "must be >= 1 (the panorama's size in pixels)";
  }
  return {};
}

}  // namespace

std::string LensValueOutOfRange(LensModel m, const double* params) {
  for (int j = 0; j < LensModelParams(m); ++j) {
    const std::string name = LensModelParamName(m, j);
    const std::string broken = RuleBroken(m, name, params[j]);
    if (!broken.empty()) {
      return std::string(Info(m).name) + "'s " + name + " is " + Value(params[j]) + ": it " + broken;
    }
  }
  return {};
}

}  // namespace dba
