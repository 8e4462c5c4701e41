// Points in space-filling-curve order and permuted; see point_order.h.
#include "dba/problem/point_order.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <type_traits>

namespace dba {
namespace {

constexpr int kBits = 21;  // per axis: 63 bits of Morton code

// The bits of v (< 2^21) spread to every third bit.
uint64_t Spread(uint64_t v) {
  v &= (uint64_t{1} << kBits) - 1;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// The [1st, 99th] percentile of axis `d` over (a sample of) the points.
std::pair<double, double> PercentileBox(std::span<const double> points, int d) {
  const int64_t n = static_cast<int64_t>(points.size()) / kPointSize;
  const int64_t step = std::max<int64_t>(1, n / 100000);
  std::vector<double> v;
  for (int64_t k = 0; k < n; k += step) {
    if (std::isfinite(points[kPointSize * k + d])) v.push_back(points[kPointSize * k + d]);
  }
  if (v.empty()) return {0.0, 1.0};
  const auto at = [&](double q) {
    auto it = v.begin() + static_cast<int64_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return *it;
  };
  const double lo = at(0.01), hi = at(0.99);
  return {lo, hi > lo ? hi : lo + 1.0};
}

}  // namespace

std::vector<int64_t> SpatialPointOrder(const Problem& problem) { return MortonOrder(problem.points); }

std::vector<int64_t> MortonOrder(std::span<const double> xyz) {
  const int64_t n = static_cast<int64_t>(xyz.size()) / kPointSize;
  // One cell size on every axis (a cube around the box): a flat survey's
  // heights must not take the code's top bits.
  std::pair<double, double> box[kPointSize];
  double side = 0.0;
  for (int d = 0; d < kPointSize; ++d) {
    box[d] = PercentileBox(xyz, d);
    side = std::max(side, box[d].second - box[d].first);
  }
  for (int d = 0; d < kPointSize; ++d) box[d].second = box[d].first + side;
  const double cells = static_cast<double>((uint64_t{1} << kBits) - 1);
  std::vector<std::pair<uint64_t, int64_t>> keyed(n);
  for (int64_t k = 0; k < n; ++k) {
    uint64_t code = 0;
    for (int d = 0; d < kPointSize; ++d) {
      const double x = xyz[kPointSize * k + d];
      double t = (x - box[d].first) / (box[d].second - box[d].first);
      t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
      code |= Spread(static_cast<uint64_t>(t * cells)) << d;
    }
    keyed[k] = {code, k};
  }
  std::sort(keyed.begin(), keyed.end());  // ties: by input position
  std::vector<int64_t> order(n);
  for (int64_t k = 0; k < n; ++k) order[k] = keyed[k].second;
  return order;
}

double SharedCameraFraction(const Problem& problem, std::span<const int64_t> order) {
  const int64_t n = problem.num_points();
  if (n < 2) return 1.0;
  const auto at = [&](int64_t k) { return order.empty() ? k : order[k]; };
  const auto& off = problem.point_offsets;
  int64_t shared = 0, pairs = 0;
  const int64_t stride = std::max<int64_t>(1, n >> 20);
  for (int64_t k = 1; k < n; k += stride) {
    ++pairs;
    const int64_t a = at(k - 1), b = at(k);
    bool common = false;
    for (int64_t i = off[a]; i < off[a + 1] && !common; ++i) {
      for (int64_t j = off[b]; j < off[b + 1]; ++j) {
        if (problem.obs_camera[i] == problem.obs_camera[j]) {
          common = true;
          break;
        }
      }
    }
    shared += common;
  }
  return static_cast<double>(shared) / static_cast<double>(pairs);
}

std::vector<int64_t> PointWalk(const Problem& problem) {
  std::vector<int64_t> walk = SpatialPointOrder(problem);
  // (Returned empty with its memory given back: clear() would keep 8 bytes
  // a point of capacity for the whole solve.)
  if (SharedCameraFraction(problem) >= 0.8 * SharedCameraFraction(problem, walk)) return {};
  return walk;
}

std::vector<int64_t> CamerasInPointOrder(const Problem& problem, std::span<const int64_t> order) {
  const int64_t n = problem.num_images();
  std::vector<int64_t> cameras;
  cameras.reserve(static_cast<size_t>(n));
  std::vector<uint8_t> seen(static_cast<size_t>(n), 0);
  // A point's new cameras by where it appears in their images (the pixel):
  // the order of its observations is the input's.
  std::vector<std::tuple<double, double, int32_t>> fresh;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    const int64_t point = order.empty() ? k : order[k];
    fresh.clear();
    for (int64_t o = problem.point_offsets[point]; o < problem.point_offsets[point + 1]; ++o) {
      const int32_t i = problem.obs_camera[o];
      if (!seen[i]) seen[i] = 1, fresh.emplace_back(problem.pixel(o)[0], problem.pixel(o)[1], i);
    }
    std::sort(fresh.begin(), fresh.end());
    for (const auto& f : fresh) cameras.push_back(std::get<2>(f));
  }
  for (int64_t i = 0; i < n; ++i) {
    if (!seen[i]) cameras.push_back(i);
  }
  return cameras;
}

std::vector<int64_t> InversePermutation(std::span<const int64_t> order) {
  std::vector<int64_t> inverse(order.size());
  for (size_t k = 0; k < order.size(); ++k) inverse[order[k]] = static_cast<int64_t>(k);
  return inverse;
}

void PermuteCameras(std::span<const int64_t> order, Problem* problem) {
  const int64_t n = problem->num_images();
  const int size = problem->camera_size();
  std::vector<double> cameras(problem->cameras.size());
  for (int64_t k = 0; k < n; ++k) {
    std::copy_n(problem->camera(order[k]), size, cameras.begin() + size * k);
  }
  std::copy(problem->cameras.begin() + size * n, problem->cameras.end(), cameras.begin() + size * n);
  problem->cameras.swap(cameras);
  auto permute = [&](auto* flags) {
    if (flags->empty()) return;
    std::remove_reference_t<decltype(*flags)> moved(flags->size());
    for (int64_t k = 0; k < n; ++k) moved[k] = (*flags)[order[k]];
    flags->swap(moved);
  };
  permute(&problem->camera_intrinsics);
  permute(&problem->fixed_cameras);
  permute(&problem->image_frame);  // rigs: the frames themselves keep their numbers
  const std::vector<int64_t> inverse = InversePermutation(order);
  for (int32_t& i : problem->obs_camera) i = static_cast<int32_t>(inverse[i]);
}

void PermutePoints(std::span<const int64_t> order, Problem* problem) {
  const int64_t n = problem->num_points();
  const std::vector<int64_t>& old_offsets = problem->point_offsets;
  std::vector<int64_t> offsets(n + 1, 0);
  for (int64_t k = 0; k < n; ++k) {
    offsets[k + 1] = offsets[k] + old_offsets[order[k] + 1] - old_offsets[order[k]];
  }
  {
    std::vector<int32_t> camera(problem->obs_camera.size());
    for (int64_t k = 0; k < n; ++k) {
      std::copy(problem->obs_camera.begin() + old_offsets[order[k]],
                problem->obs_camera.begin() + old_offsets[order[k] + 1], camera.begin() + offsets[k]);
    }
    problem->obs_camera.swap(camera);
  }
  {
    std::vector<double> pixel(problem->obs_pixel.size());
    for (int64_t k = 0; k < n; ++k) {
      std::copy(problem->obs_pixel.begin() + 2 * old_offsets[order[k]],
                problem->obs_pixel.begin() + 2 * old_offsets[order[k] + 1], pixel.begin() + 2 * offsets[k]);
    }
    problem->obs_pixel.swap(pixel);
  }
  {
    std::vector<double> points(problem->points.size());
    for (int64_t k = 0; k < n; ++k) {
      std::copy_n(problem->points.begin() + kPointSize * order[k], kPointSize,
                  points.begin() + kPointSize * k);
    }
    problem->points.swap(points);
  }
  problem->point_offsets.swap(offsets);
  if (!problem->point_priors.empty()) {
    const std::vector<int64_t> inverse = InversePermutation(order);
    for (PointPrior& p : problem->point_priors) p.point = inverse[p.point];
    std::sort(problem->point_priors.begin(), problem->point_priors.end(),
              [](const PointPrior& a, const PointPrior& b) { return a.point < b.point; });
  }
}

}  // namespace dba
