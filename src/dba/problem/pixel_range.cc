// The range of an observed pixel; see pixel_range.h.
#include "dba/problem/pixel_range.h"

#include <cmath>
#include <cstdio>

namespace dba {

std::string PixelOutOfRange(double x, double y) {
  const bool finite = std::isfinite(x) && std::isfinite(y);
  if (finite && std::abs(x) <= kMaxPixelMagnitude && std::abs(y) <= kMaxPixelMagnitude) return "";
  char text[160];
  std::snprintf(text, sizeof text, "pixel (%.10g, %.10g) %s", x, y,
                finite ? "is beyond 1e7 px from the origin: no image is that large"
                       : "is not finite");
  return text;
}

}  // namespace dba
