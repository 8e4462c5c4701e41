// A generated UAV survey (synthetic/uav_generator.h, footprint by footprint)
// with its points renumbered at random: an input whose order is scattered,
// as a shuffled file's, for tests of the walk (problem/point_order.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba::testing {

struct ScatteredSurvey {
  Problem spatial;             // as generated
  Problem scattered;           // the same points renumbered
  std::vector<int64_t> order;  // scattered point k is spatial point order[k]
};

// `images` images of `features` tie points each, generated with `seed` into
// a temporary file named `name`, the points shuffled with `shuffle_seed`.
ScatteredSurvey MakeScatteredSurvey(const std::string& name, int64_t images, int64_t features,
                                    uint32_t seed, uint32_t shuffle_seed);

}  // namespace dba::testing
