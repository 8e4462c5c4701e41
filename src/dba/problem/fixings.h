// What a solve holds fixed, as data: whole images (a BAL camera's 9
// parameters, a pose's 6) by their 0-based index in the problem, and
// intrinsic parameters in every group (photogrammetric model). Fixed
// parameters are not unknowns (rcs/unknown_layout.h).
//
// The command line's fixings (app/solve_input.h) become these after they are
// checked against the input; the ranks of a distributed solve that read a
// binary file apply the same Fixings to the camera side they read.
// Thread safety: values; ApplyFixings writes only *problem.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct Fixings {
  std::vector<int64_t> images;  // 0-based image indices
  uint8_t intrinsics = 0;       // IntrinsicBit mask held in every group
  bool empty() const { return images.empty() && intrinsics == 0; }
};

// Adds `f` to what the camera side already holds fixed. std::invalid_argument for
// an image index out of range or fixed intrinsics of a BAL problem.
inline void ApplyFixings(const Fixings& f, CameraSide* problem) {
  if (!f.images.empty()) {
    problem->fixed_cameras.resize(problem->num_images(), 0);
    for (int64_t i : f.images) {
      if (i < 0 || i >= problem->num_images()) {
        throw std::invalid_argument("image " + std::to_string(i) + " does not exist (the problem has " +
                                    std::to_string(problem->num_images()) + " images, 0-based)");
      }
      problem->fixed_cameras[i] = 1;
    }
  }
  if (f.intrinsics != 0) {
    if (problem->model != CameraModel::kPhoto) {
      throw std::invalid_argument("fixed intrinsics need the photogrammetric model");
    }
    problem->fixed_intrinsics.resize(problem->num_groups(), 0);
    for (uint8_t& m : problem->fixed_intrinsics) m |= f.intrinsics;
  }
}

}  // namespace dba
