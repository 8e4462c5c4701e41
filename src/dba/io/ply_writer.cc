// Binary PLY point clouds; see ply_writer.h.
#include "dba/io/ply_writer.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "dba/io/atomic_output_file.h"

namespace dba {
namespace {

constexpr size_t kRecordBytes = 3 * sizeof(double) + 3;
constexpr size_t kFlushBytes = size_t{1} << 20;

// The p-quantile (p in [0, 1]) of sorted values, interpolating linearly
// between order statistics.
double Quantile(const std::vector<double>& sorted, double p) {
  const double pos = p * static_cast<double>(sorted.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double w = pos - static_cast<double>(lo);
  return sorted[lo] + w * (sorted[hi] - sorted[lo]);
}

void AppendDouble(double v, std::string* out) {
  uint64_t bits = std::bit_cast<uint64_t>(v);
  for (int b = 0; b < 8; ++b) {
    out->push_back(static_cast<char>(bits & 0xff));
    bits >>= 8;
  }
}

}  // namespace

std::array<uint8_t, 3> HeightColour(double t) {
  if (!(t > 0)) t = 0;  // also NaN
  if (t > 1) t = 1;
  auto level = [](double s) { return static_cast<uint8_t>(std::lround(255.0 * s)); };
  const double s = 4.0 * t;
  if (s <= 1) return {0, level(s), 255};               // blue -> cyan
  if (s <= 2) return {0, 255, level(2 - s)};           // cyan -> green
  if (s <= 3) return {level(s - 2), 255, 0};           // green -> yellow
  return {255, level(4 - s), 0};                       // yellow -> red
}

std::vector<uint8_t> RampColours(std::span<const double> values) {
  std::vector<double> finite;
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  std::sort(finite.begin(), finite.end());
  const double lo = finite.empty() ? 0.0 : Quantile(finite, 0.01);
  const double hi = finite.empty() ? 0.0 : Quantile(finite, 0.99);
  std::vector<uint8_t> rgb;
  rgb.reserve(3 * values.size());
  for (double v : values) {
    const std::array<uint8_t, 3> c = !std::isfinite(v) ? HeightColour(0)
                                     : !(hi > lo)      ? HeightColour(0.5)
                                                       : HeightColour((v - lo) / (hi - lo));
    rgb.insert(rgb.end(), c.begin(), c.end());
  }
  return rgb;
}

void WritePointCloudPly(const std::string& path, std::span<const double> xyz,
                        std::span<const uint8_t> rgb) {
  if (xyz.size() % 3 != 0) {
    throw std::invalid_argument("WritePointCloudPly: xyz has " + std::to_string(xyz.size()) +
                                " values, not a multiple of 3");
  }
  if (!rgb.empty() && rgb.size() != xyz.size()) {
    throw std::invalid_argument("WritePointCloudPly: rgb has " + std::to_string(rgb.size()) +
                                " values for " + std::to_string(xyz.size() / 3) + " points");
  }
  const size_t n = xyz.size() / 3;
  std::vector<uint8_t> height;
  if (rgb.empty()) {  // height colours
    std::vector<double> z(n);
    for (size_t k = 0; k < n; ++k) z[k] = xyz[3 * k + 2];
    height = RampColours(z);
    rgb = height;
  }
  auto colour = [&](size_t k) -> std::array<uint8_t, 3> {
    return {rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2]};
  };

  AtomicOutputFile out(path);
  std::string buf =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment written by dba\n"
      "element vertex " +
      std::to_string(n) +
      "\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "property uchar red\n"
      "property uchar green\n"
      "property uchar blue\n"
      "end_header\n";
  auto flush = [&] {
    errno = 0;
    if (!buf.empty() && std::fwrite(buf.data(), 1, buf.size(), out.file()) != buf.size()) {
      out.Fail("write failed", errno);
    }
    buf.clear();
  };
  buf.reserve(kFlushBytes + kRecordBytes);
  for (size_t k = 0; k < n; ++k) {
    for (int d = 0; d < 3; ++d) AppendDouble(xyz[3 * k + d], &buf);
    for (uint8_t c : colour(k)) buf.push_back(static_cast<char>(c));
    if (buf.size() >= kFlushBytes) flush();
  }
  flush();
  out.Commit();
}

}  // namespace dba
