// Seeded random renumbering; see random_renumbering.h.
#include "dba/problem/random_renumbering.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "dba/problem/point_order.h"

namespace dba {
namespace {

// new position -> old: Fisher–Yates with an explicit draw (std::shuffle and
// the standard distributions differ between library versions).
std::vector<int64_t> RandomPermutation(int64_t n, std::mt19937_64* engine) {
  std::vector<int64_t> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), int64_t{0});
  for (int64_t i = n - 1; i > 0; --i) {
    const uint64_t j = (*engine)() % static_cast<uint64_t>(i + 1);
    std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(j)]);
  }
  return order;
}

}  // namespace

void RenumberAtRandom(uint64_t seed, Problem* problem) {
  std::mt19937_64 engine(seed);
  PermuteCameras(RandomPermutation(problem->num_images(), &engine), problem);
  PermutePoints(RandomPermutation(problem->num_points(), &engine), problem);
  // Each point's observations by camera, pixels alongside.
  std::vector<std::pair<int32_t, int64_t>> keyed;
  std::vector<double> pixels;
  for (int64_t k = 0; k < problem->num_points(); ++k) {
    const int64_t begin = problem->point_offsets[k], end = problem->point_offsets[k + 1];
    keyed.clear();
    for (int64_t o = begin; o < end; ++o) keyed.emplace_back(problem->obs_camera[o], o);
    std::sort(keyed.begin(), keyed.end());
    pixels.assign(problem->obs_pixel.begin() + 2 * begin, problem->obs_pixel.begin() + 2 * end);
    for (int64_t a = 0; a < end - begin; ++a) {
      problem->obs_camera[begin + a] = keyed[a].first;
      problem->obs_pixel[2 * (begin + a)] = pixels[2 * (keyed[a].second - begin)];
      problem->obs_pixel[2 * (begin + a) + 1] = pixels[2 * (keyed[a].second - begin) + 1];
    }
  }
}

}  // namespace dba
