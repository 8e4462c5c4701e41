// BAL text parser: tokens via std::from_chars over the line buffer, then a
// stable counting sort of the observations by point; see bal_reader.h.
#include "dba/io/bal_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/bz2_line_reader.h"

namespace dba {
namespace {

// Upper bound on what is reserved from header counts before the data has been
// seen, so a lying header fails with "end of file", not with bad_alloc.
constexpr int64_t kMaxReserve = int64_t{1} << 22;
constexpr int64_t kMaxCameras = int64_t{1} << 31;  // camera ids are int32

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Whitespace-separated tokens over the lines of a Bz2LineReader. Every
// message built through `what` reads "expected <what>, found ...".
class Parser {
 public:
  explicit Parser(const std::string& path) : reader_(path) {}

  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(reader_.path(), std::max<int64_t>(reader_.line_number(), 1),
                     message);
  }

  // Next token, or false at end of file.
  bool Next(std::string_view* token) {
    for (;;) {
      while (pos_ < line_.size() && IsSpace(line_[pos_])) ++pos_;
      if (pos_ < line_.size()) break;
      if (!reader_.ReadLine(&line_)) return false;
      pos_ = 0;
    }
    size_t start = pos_;
    while (pos_ < line_.size() && !IsSpace(line_[pos_])) ++pos_;
    *token = line_.substr(start, pos_ - start);
    return true;
  }

  template <class What>
  std::string_view Token(const What& what) {
    std::string_view t;
    if (!Next(&t)) {
      Fail("expected " + what() +
           ", found end of file (the file is shorter than its header says)");
    }
    return t;
  }

  template <class What>
  int64_t Int(const What& what) {
    std::string_view t = Token(what);
    int64_t v = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range) {
      Fail("expected " + what() + ", found '" + std::string(t) +
           "' (out of the 64-bit integer range)");
    }
    if (ec != std::errc() || end != t.data() + t.size()) {
      Fail("expected " + what() + ", found '" + std::string(t) +
           "' (not an integer)");
    }
    return v;
  }

  template <class What>
  double Double(const What& what) {
    std::string_view t = Token(what);
    const char* first = t.data();
    const char* last = t.data() + t.size();
    if (t.size() > 1 && *first == '+' && first[1] != '-') ++first;
    double v = 0;
    auto [end, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range) {
      Fail("expected " + what() + ", found '" + std::string(t) +
           "' (out of the double range)");
    }
    if (ec != std::errc() || end != last) {
      Fail("expected " + what() + ", found '" + std::string(t) +
           "' (not a number)");
    }
    if (!std::isfinite(v)) {
      Fail("expected " + what() + ", found non-finite value '" + std::string(t) +
           "'");
    }
    return v;
  }

 private:
  Bz2LineReader reader_;
  std::string_view line_;
  size_t pos_ = 0;
};

std::string Str(int64_t v) { return std::to_string(v); }

}  // namespace

BalProblem ReadBal(const std::string& path) {
  Parser in(path);

  // Header.
  auto header = [] {
    return std::string("header 'num_cameras num_points num_observations'");
  };
  const int64_t num_cameras = in.Int(header);
  if (num_cameras <= 0) in.Fail("num_cameras must be positive, found " + Str(num_cameras));
  if (num_cameras > kMaxCameras) {
    in.Fail("num_cameras " + Str(num_cameras) +
            " exceeds the 32-bit camera id limit " + Str(kMaxCameras));
  }
  const int64_t num_points = in.Int(header);
  if (num_points <= 0) in.Fail("num_points must be positive, found " + Str(num_points));
  const int64_t num_observations = in.Int(header);
  if (num_observations <= 0) {
    in.Fail("num_observations must be positive, found " + Str(num_observations));
  }
  if (num_points > num_observations) {
    in.Fail("num_points " + Str(num_points) + " exceeds num_observations " +
            Str(num_observations) + ": every point needs an observation");
  }

  // Observations in file order.
  std::vector<int32_t> file_camera;
  std::vector<int64_t> file_point;
  std::vector<double> file_pixel;
  file_camera.reserve(std::min(num_observations, kMaxReserve));
  file_point.reserve(std::min(num_observations, kMaxReserve));
  file_pixel.reserve(2 * std::min(num_observations, kMaxReserve));
  for (int64_t j = 0; j < num_observations; ++j) {
    auto what = [&] {
      return "observation " + Str(j) + " of " + Str(num_observations) +
             " ('camera point x y')";
    };
    const int64_t c = in.Int(what);
    if (c < 0 || c >= num_cameras) {
      in.Fail("camera index " + Str(c) + " of observation " + Str(j) +
              " is out of range [0, " + Str(num_cameras) + ")");
    }
    const int64_t k = in.Int(what);
    if (k < 0 || k >= num_points) {
      in.Fail("point index " + Str(k) + " of observation " + Str(j) +
              " is out of range [0, " + Str(num_points) + ")");
    }
    file_camera.push_back(static_cast<int32_t>(c));
    file_point.push_back(k);
    file_pixel.push_back(in.Double(what));
    file_pixel.push_back(in.Double(what));
  }

  BalProblem problem;
  // Cameras.
  problem.cameras.reserve(kBalCameraSize * std::min(num_cameras, kMaxReserve));
  for (int64_t i = 0; i < num_cameras; ++i) {
    auto what = [&] {
      return Str(kBalCameraSize) + " camera parameters for camera " + Str(i);
    };
    for (int q = 0; q < kBalCameraSize; ++q) problem.cameras.push_back(in.Double(what));
  }
  problem.cameras.shrink_to_fit();

  // Points (num_points <= num_observations, which are now in memory, so these
  // allocations are backed by real data).
  std::vector<int64_t>& offsets = problem.point_offsets;
  offsets.assign(num_points + 1, 0);
  for (int64_t k : file_point) ++offsets[k + 1];
  problem.points.resize(kPointSize * num_points);
  for (int64_t k = 0; k < num_points; ++k) {
    auto what = [&] {
      return Str(kPointSize) + " coordinates for point " + Str(k);
    };
    for (int q = 0; q < kPointSize; ++q) problem.points[kPointSize * k + q] = in.Double(what);
    if (offsets[k + 1] == 0) in.Fail("point " + Str(k) + " has no observation");
  }
  std::string_view extra;
  if (in.Next(&extra)) {
    in.Fail("expected end of file after the last point coordinate, found '" +
            std::string(extra) + "' (do the header counts match the data?)");
  }

  // Stable counting sort by point: offsets[k] .. offsets[k+1] is point k.
  for (int64_t k = 0; k < num_points; ++k) offsets[k + 1] += offsets[k];
  std::vector<int64_t> next(offsets.begin(), offsets.end() - 1);
  problem.obs_camera.resize(num_observations);
  problem.obs_pixel.resize(2 * num_observations);
  for (int64_t j = 0; j < num_observations; ++j) {
    const int64_t d = next[file_point[j]]++;
    problem.obs_camera[d] = file_camera[j];
    problem.obs_pixel[2 * d] = file_pixel[2 * j];
    problem.obs_pixel[2 * d + 1] = file_pixel[2 * j + 1];
  }
  return problem;
}

}  // namespace dba
