// What a solve holds fixed, as data: whole images (a BAL camera's 9
// parameters, a pose's 6) by their 0-based index in the problem, and
// intrinsic parameters by name, in every group or in one (photogrammetric
// model). Names are each group's lens model's (problem/lens_model.h: COLMAP's
// own names, e.g. k0…k5 and p0, p1 for RAD_TAN_THIN_PRISM_FISHEYE), the
// kinds every model has (focal, principal_point, extra: LensModelKindMask),
// or "all". Fixed parameters are not unknowns (rcs/unknown_layout.h).
//
// The command line's fixings (session/solve_input.h) become these after they are
// checked against the input; the ranks of a distributed solve that read a
// binary file apply the same Fixings to the camera side they read.
// Thread safety: values; ApplyFixings writes only *problem.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

// `names` held fixed in group `group` (0-based), or in every group (-1).
struct IntrinsicFixing {
  int64_t group = -1;
  std::vector<std::string> names;
  bool operator==(const IntrinsicFixing&) const = default;
};

struct Fixings {
  std::vector<int64_t> images;  // 0-based image indices
  std::vector<IntrinsicFixing> intrinsics;
  bool all_images = false;       // every image (--fix-images all)
  // Every group's principal point (kPhoto; nothing in a BAL problem): the
  // default unless --refine-principal-point.
  bool principal_point = false;
  // Rigs: the sensor poses held (--rig-geometry): every refined one, or
  // those of these groups (0-based); not a rig's sensor: invalid_argument.
  bool all_sensors = false;
  std::vector<int64_t> sensors;
  bool empty() const {
    return images.empty() && intrinsics.empty() && !all_images && !principal_point &&
           !all_sensors && sensors.empty();
  }
};

// Adds `f` to what the camera side already holds fixed: each name to the
// groups it targets whose model has it; a refined sensor pose becomes held,
// also the sensor of every held image (its pose is its frame's, held, and
// its sensor's: docs/design.md §1.7). std::invalid_argument for an image
// or group index out of range, fixed intrinsics of a BAL problem, and a name
// that none of the targeted groups' models has (listing their models and
// parameter names). Nothing is changed when it throws.
void ApplyFixings(const Fixings& f, CameraSide* problem);

// The fixed-intrinsics masks ApplyFixings would leave (empty when none):
// the same checks, for checking a command line against a camera side
// without changing it.
std::vector<uint16_t> FixedIntrinsicsAfter(const Fixings& f, const CameraSide& side);

}  // namespace dba
