// The range of an observed pixel, in every input (BAL text, .dba, COLMAP
// points2D, control points' measurements, Python's arrays): finite, and no
// coordinate beyond 1e7 px from the origin. An image is at most 1e6 px a
// side (io/colmap_model's bound on a camera's width and height) and a pixel
// convention puts the origin at a corner (COLMAP) or the centre (BAL), so a
// coordinate ten times that is a blunder, not a measurement: one BAL pixel
// of 1e80 ended a solve with exit 0, a cost of 5e159 and nothing moved.
//
// Thread safety: pure functions.
#pragma once

#include <string>

namespace dba {

constexpr double kMaxImageSidePixels = 1e6;
constexpr double kMaxPixelMagnitude = 10 * kMaxImageSidePixels;

// Why (x, y) is no observed pixel ("pixel (1e+80, 262.09) is beyond 1e7 px
// from the origin: no image is that large"); empty when it is in range.
std::string PixelOutOfRange(double x, double y);

}  // namespace dba
