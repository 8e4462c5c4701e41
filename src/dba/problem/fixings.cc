// Marking fixed parameters; see fixings.h.
#include "dba/problem/fixings.h"

#include <algorithm>
#include <stdexcept>

namespace dba {
namespace {

// "RADIAL (f, cx, cy, k1, k2), OPENCV (...)": the distinct models of `groups`.
std::string ModelsOf(const CameraSide& side, int64_t first, int64_t last) {
  std::vector<LensModel> seen;
  std::string s;
  for (int64_t g = first; g < last; ++g) {
    const LensModel m = side.group_model(g);
    if (std::find(seen.begin(), seen.end(), m) != seen.end()) continue;
    seen.push_back(m);
    if (!s.empty()) s += ", ";
    s += std::string(Info(m).name) + " (" + Info(m).params + ")";
  }
  return s;
}

}  // namespace

std::vector<uint16_t> FixedIntrinsicsAfter(const Fixings& f, const CameraSide& side) {
  if (!f.intrinsics.empty() && side.model != CameraModel::kPhoto) {
    throw std::invalid_argument("fixed intrinsics need the photogrammetric model");
  }
  const int64_t groups = side.num_groups();
  std::vector<uint16_t> fixed = side.fixed_intrinsics;
  if (!f.intrinsics.empty()) fixed.resize(groups, 0);
  for (const IntrinsicFixing& x : f.intrinsics) {
    if (x.group < -1 || x.group >= groups) {
      throw std::invalid_argument("intrinsic group " + std::to_string(x.group) +
                                  " does not exist (the problem has " + std::to_string(groups) +
                                  " groups, 0-based)");
    }
    const int64_t first = x.group < 0 ? 0 : x.group, last = x.group < 0 ? groups : x.group + 1;
    for (const std::string& name : x.names) {
      bool found = false;
      for (int64_t g = first; g < last; ++g) {
        const LensModel m = side.group_model(g);
        if (name == "all") {
          fixed[g] |= LensModelParamMask(m);
          found = true;
        } else if (const std::optional<uint16_t> kind = LensModelKindMask(m, name)) {
          fixed[g] |= *kind;
          found = true;
        } else if (const std::optional<int> j = LensModelParamIndex(m, name)) {
          fixed[g] |= static_cast<uint16_t>(1u << *j);
          found = true;
        }
      }
      if (!found && first < last) {
        throw std::invalid_argument(
            "no intrinsic parameter '" + name + "' in " +
            (x.group < 0 ? std::string("any group's model")
                         : "group " + std::to_string(x.group) + "'s model") +
            "; the models are " + ModelsOf(side, first, last));
      }
    }
  }
  if (f.principal_point && side.model == CameraModel::kPhoto) {
    fixed.resize(groups, 0);
    for (int64_t g = 0; g < groups; ++g) {
      fixed[g] |= *LensModelKindMask(side.group_model(g), "principal_point");
    }
  }
  return fixed;
}

void ApplyFixings(const Fixings& f, CameraSide* problem) {
  for (int64_t i : f.images) {
    if (i < 0 || i >= problem->num_images()) {
      throw std::invalid_argument("image " + std::to_string(i) + " does not exist (the problem has " +
                                  std::to_string(problem->num_images()) + " images, 0-based)");
    }
  }
  for (int64_t g : f.sensors) {
    if (!problem->has_rigs() || g < 0 || g >= problem->num_groups()) {
      throw std::invalid_argument(
          "sensor " + std::to_string(g) + ": " +
          (problem->has_rigs() ? "no such intrinsic group (the problem has " +
                                     std::to_string(problem->num_groups()) + ", 0-based)"
                               : std::string("the problem has no rigs")));
    }
  }
  std::vector<uint16_t> fixed = FixedIntrinsicsAfter(f, *problem);
  if (!f.images.empty() || f.all_images) {
    problem->fixed_cameras.resize(problem->num_images(), 0);
    for (int64_t i : f.images) problem->fixed_cameras[i] = 1;
    if (f.all_images) std::fill(problem->fixed_cameras.begin(), problem->fixed_cameras.end(), 1);
  }
  // A held image's pose is its frame's (held by the layout) composed with
  // its sensor's: the sensor is held too, in every frame.
  std::vector<uint8_t> held(problem->sensor_kind.size(), f.all_sensors ? 1 : 0);
  for (int64_t g : f.sensors) held[g] = 1;
  for (int64_t i = 0; problem->has_rigs() && i < problem->num_images(); ++i) {
    if (problem->camera_fixed(i)) held[problem->camera_intrinsics[i]] = 1;
  }
  for (size_t g = 0; g < held.size(); ++g) {
    if (held[g] && problem->sensor_kind[g] == kSensorRefined) problem->sensor_kind[g] = kSensorHeld;
  }
  problem->fixed_intrinsics = std::move(fixed);
}

}  // namespace dba
