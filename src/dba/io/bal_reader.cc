// BAL text: read in parallel (io/bal_parallel_reader), or, for any file that
// reader does not take, line by line here: tokens and numbers by
// io/text_tokens over the lines, observations to their point-major place by
// io/point_major_order; see bal_reader.h.
#include "dba/io/bal_reader.h"

#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <cmath>
#include <cstdint>
#include <new>
#include <string_view>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/bal_parallel_reader.h"
#include "dba/io/point_major_order.h"
#include "dba/io/text_line_reader.h"
#include "dba/io/text_tokens.h"
#include "dba/problem/pixel_range.h"

namespace dba {
namespace {

// Upper bound on what is reserved from header counts before the data has been
// seen, so a lying header fails with "end of file", not with bad_alloc.
constexpr int64_t kMaxReserve = int64_t{1} << 22;

// Whitespace-separated tokens over the lines of a TextLineReader. Every
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
    while (!tokens_.Next(token)) {
      std::string_view line;
      if (!reader_.ReadLine(&line)) return false;
      // A file cut short may end inside its last number, which would still
      // parse: a last value must be followed by a blank or a line end.
      if (reader_.last_line_unterminated() && !line.empty() && !IsBlank(line.back())) {
        Fail("the file ends inside this line (no line end after the last value): cut short?");
      }
      tokens_ = LineTokens(line);
    }
    return true;
  }

  // Tokens left on the current line (not consumed).
  int TokensLeftOnLine() const { return tokens_.Remaining(); }

  // The most observations worth reserving for: a plain file holds at most
  // one per 8 bytes ("c p x y" and a newline). A bzip2 file's content size
  // is not known before it is read; BAL text compresses 3-5x, so 64x its
  // size bounds any real file (beyond it the vectors grow as data comes).
  int64_t MaxObservations(const std::string& path) const {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return kMaxReserve;
    const int64_t content = static_cast<int64_t>(size) * (reader_.is_bz2() ? 64 : 1);
    return content / 8 + 1;
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
    switch (ParseInteger(t, &v)) {
      case NumberStatus::kOk: return v;
      case NumberStatus::kOutOfRange:
        Fail("expected " + what() + ", found '" + Clipped(t) +
             "' (out of the 64-bit integer range)");
      default:
        Fail("expected " + what() + ", found '" + Clipped(t) + "' (not an integer)");
    }
  }

  template <class What>
  double Double(const What& what) {
    std::string_view t = Token(what);
    double v = 0;
    switch (ParseDouble(t, &v)) {
      case NumberStatus::kOk: return v;
      case NumberStatus::kOutOfRange:
        Fail("expected " + what() + ", found '" + Clipped(t) + "' (out of the double range)");
      case NumberStatus::kNotFinite:
        Fail("expected " + what() + ", found non-finite value '" + Clipped(t) + "'");
      default:
        Fail("expected " + what() + ", found '" + Clipped(t) + "' (not a number)");
    }
  }

 private:
  TextLineReader reader_;
  LineTokens tokens_;  // of the current line
};

std::string Str(int64_t v) { return std::to_string(v); }

// push_back that grows the capacity by doubling but never past `limit` (the
// header's count), so a truthful header leaves no slack to shrink away.
template <typename T>
void PushCapped(std::vector<T>& v, T value, int64_t limit) {
  if (v.size() == v.capacity()) {
    v.reserve(static_cast<size_t>(std::min<int64_t>(
        limit, std::max<int64_t>(2 * static_cast<int64_t>(v.capacity()), 1024))));
  }
  v.push_back(value);
}

struct Header {
  int64_t cameras = 0, points = 0, observations = 0;
  int extra = 0;  // tokens after the third on its line
};

Header ReadHeader(Parser& in) {
  auto header = [] {
    return std::string("header 'num_cameras num_points num_observations'");
  };
  Header h;
  h.cameras = in.Int(header);
  if (h.cameras <= 0) in.Fail("num_cameras must be positive, found " + Str(h.cameras));
  if (h.cameras > kMaxBalCameras) {
    in.Fail("num_cameras " + Str(h.cameras) + " exceeds the 32-bit camera id limit " +
            Str(kMaxBalCameras));
  }
  h.points = in.Int(header);
  if (h.points <= 0) in.Fail("num_points must be positive, found " + Str(h.points));
  h.observations = in.Int(header);
  // Tokens may split over lines any way, but a header line with one number
  // too many (four counts, or a first observation glued on) is the likely
  // cause when the first observation then fails: say so there.
  h.extra = in.TokensLeftOnLine();
  if (h.observations <= 0) {
    in.Fail("num_observations must be positive, found " + Str(h.observations));
  }
  if (h.points > h.observations) {
    in.Fail("num_points " + Str(h.points) + " exceeds num_observations " +
            Str(h.observations) + ": every point needs an observation");
  }
  return h;
}

// Observations, written straight into their point-major place while the
// file lists them grouped by point (as BAL files do): then no copy of the
// observations is ever made. Only if a point index goes down does `order`
// start recording point indices, to sort at the end.
void ReadObservations(Parser& in, const std::string& path, const Header& h, Problem* problem,
                      PointMajorOrder* order) {
  // Reserve what the header says, as far as the file can hold it: pages are
  // only backed once written, so a header that lies costs address space,
  // not memory, but a plain file's size bounds even that (a 43-byte file
  // claiming 182M observations made 2.9 GB of reservations; fuzz/run.sh). If
  // even the address space is refused, grow as the data comes.
  const int64_t reserve = std::min(h.observations, in.MaxObservations(path));
  try {
    problem->obs_camera.reserve(reserve);
    problem->obs_pixel.reserve(2 * reserve);
  } catch (const std::bad_alloc&) {
    std::vector<int32_t>().swap(problem->obs_camera);
    std::vector<double>().swap(problem->obs_pixel);
  }
  for (int64_t j = 0; j < h.observations; ++j) {
    auto what = [&] {
      return "observation " + Str(j) + " of " + Str(h.observations) + " ('camera point x y')";
    };
    const int64_t c = in.Int(what);
    if (c < 0 || c >= h.cameras) {
      in.Fail("camera index " + Str(c) + " of observation " + Str(j) + " is out of range [0, " +
              Str(h.cameras) + ")" +
              (j == 0 && h.extra % 4 != 0
                   ? " (the header's line has " + Str(h.extra) +
                         " more value(s) after 'num_cameras num_points num_observations': a "
                         "BAL header holds exactly three)"
                   : std::string()));
    }
    const int64_t k = in.Int(what);
    if (k < 0 || k >= h.points) {
      in.Fail("point index " + Str(k) + " of observation " + Str(j) + " is out of range [0, " +
              Str(h.points) + ")");
    }
    PushCapped(problem->obs_camera, static_cast<int32_t>(c), h.observations);
    const double x = in.Double(what), y = in.Double(what);
    const std::string out_of_range = PixelOutOfRange(x, y);
    if (!out_of_range.empty()) in.Fail("observation " + Str(j) + ": " + out_of_range);
    PushCapped(problem->obs_pixel, x, 2 * h.observations);
    PushCapped(problem->obs_pixel, y, 2 * h.observations);
    order->Add(k);
  }
}

}  // namespace

Problem ReadBalLineByLine(const std::string& path) {
  Parser in(path);
  const Header h = ReadHeader(in);
  const int64_t num_cameras = h.cameras, num_points = h.points;
  Problem problem;
  PointMajorOrder order;
  ReadObservations(in, path, h, &problem, &order);

  // Cameras.
  problem.cameras.reserve(kBalCameraSize * std::min(num_cameras, kMaxReserve));
  for (int64_t i = 0; i < num_cameras; ++i) {
    auto what = [&] {
      return Str(kBalCameraSize) + " camera parameters for camera " + Str(i);
    };
    for (int q = 0; q < kBalCameraSize; ++q) problem.cameras.push_back(in.Double(what));
  }
  problem.cameras.shrink_to_fit();

  // Points (num_points <= num_observations, which are now in memory, so this
  // allocation is backed by real data).
  problem.points.resize(kPointSize * num_points);
  for (int64_t k = 0; k < num_points; ++k) {
    auto what = [&] {
      return Str(kPointSize) + " coordinates for point " + Str(k);
    };
    for (int q = 0; q < kPointSize; ++q) problem.points[kPointSize * k + q] = in.Double(what);
    if (order.count(k) == 0) in.Fail("point " + Str(k) + " has no observation");
  }
  std::string_view extra;
  if (in.Next(&extra)) {
    in.Fail("expected end of file after the last point coordinate, found '" +
            Clipped(extra) + "' (do the header counts match the data?)");
  }
  order.Finish(num_points, &problem);
  return problem;
}

Problem ReadBal(const std::string& path, int threads) {
  // A pipe or FIFO can be read only once: line by line, its message whole.
  std::error_code not_regular;
  if (!std::filesystem::is_regular_file(path, not_regular)) return ReadBalLineByLine(path);
  std::optional<Problem> problem =
      ReadBalInParallel(path, threads > 0 ? threads : omp_get_max_threads());
  if (problem.has_value()) return std::move(*problem);
  // Not a file the parallel reader takes as it is: read line by line, for
  // the message naming the line (or, for a valid file it does not take
  // whole, the problem).
  return ReadBalLineByLine(path);
}

}  // namespace dba
