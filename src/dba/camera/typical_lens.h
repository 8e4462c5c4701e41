// Plausible parameters of each lens model, for generated surveys and tests:
// a given focal length (PINHOLE-style models get fy = 1.002 fx, so a solver
// that ties them is caught), the principal point a few pixels off the image
// centre, and distortion of the size real lenses of that kind show.
//
// Thread safety: pure function.
#pragma once

#include <vector>

#include "dba/problem/lens_model.h"

namespace dba {

std::vector<double> TypicalLensParams(LensModel model, double focal, double width,
                                      double height);

}  // namespace dba
