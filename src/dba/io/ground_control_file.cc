// Reading ground control and check points; see ground_control_file.h.
#include "dba/io/ground_control_file.h"

#include <unordered_map>

#include "dba/common/error.h"
#include "dba/io/sigma_fields.h"
#include "dba/io/text_line_reader.h"
#include "dba/io/text_tokens.h"
#include "dba/problem/pixel_range.h"

namespace dba {
namespace {

double Number(const std::string& path, int64_t line, const char* what, const std::string& field) {
  double v = 0.0;
  if (ParseDouble(field, &v) != NumberStatus::kOk) {
    throw InputError(path, line, std::string(what) + ": '" + Clipped(field) + "' is not a finite number");
  }
  return v;
}

struct PendingMeasurement {
  std::string point;
  GroundControlMeasurementRow row;
};

}  // namespace

std::vector<GroundControlRow> ReadGroundControlFile(const std::string& path) {
  TextLineReader in(path);
  std::vector<GroundControlRow> points;
  std::unordered_map<std::string, size_t> index;  // name -> points[]
  std::vector<PendingMeasurement> measurements;
  std::string_view view;
  while (in.ReadLine(&view)) {
    const int64_t line = in.line_number();
    const std::vector<std::string> f = CommentFreeFields(view);
    if (f.empty()) continue;
    if (f.size() == 4) {
      const double x = Number(path, line, "x", f[2]), y = Number(path, line, "y", f[3]);
      const std::string out_of_range = PixelOutOfRange(x, y);
      if (!out_of_range.empty()) throw InputError(path, line, "measurement: " + out_of_range);
      measurements.push_back({f[0], {f[1], {x, y}, line}});
      continue;
    }
    if (f.size() != 7) {
      throw InputError(path, line,
                       "expected a point, NAME X Y Z SIGMA_XY SIGMA_Z control|check (7 fields), "
                       "or a measurement, NAME IMAGE x y (4 fields); got " +
                           std::to_string(f.size()) + " fields");
    }
    GroundControlRow p;
    p.name = f[0];
    p.line = line;
    p.xyz = {Number(path, line, "X", f[1]), Number(path, line, "Y", f[2]),
             Number(path, line, "Z", f[3])};
    p.sigma = {Number(path, line, "SIGMA_XY", f[4]), Number(path, line, "SIGMA_Z", f[5])};
    CheckSigmas(path, line, p.sigma[0], p.sigma[1], f[4], f[5]);
    if (f[6] != "control" && f[6] != "check") {
      throw InputError(path, line, "role '" + Clipped(f[6]) + "': expected control or check");
    }
    p.control = f[6] == "control";
    const auto [it, fresh] = index.emplace(p.name, points.size());
    if (!fresh) {
      throw InputError(path, line, "point '" + Clipped(p.name) + "' is already defined (line " +
                                       std::to_string(points[it->second].line) + ")");
    }
    points.push_back(std::move(p));
  }
  if (points.empty()) throw InputError(path, 0, "no points (every line blank, a comment or a measurement)");
  for (PendingMeasurement& m : measurements) {
    const auto it = index.find(m.point);
    if (it == index.end()) {
      throw InputError(path, m.row.line, "measurement of '" + Clipped(m.point) +
                                             "', which no line NAME X Y Z SIGMA_XY SIGMA_Z ROLE defines");
    }
    GroundControlRow& p = points[it->second];
    for (const GroundControlMeasurementRow& other : p.measurements) {
      if (other.image == m.row.image) {
        throw InputError(path, m.row.line, "point '" + Clipped(m.point) + "' is already measured in image '" +
                                               m.row.image + "' (line " + std::to_string(other.line) + ")");
      }
    }
    p.measurements.push_back(std::move(m.row));
  }
  for (const GroundControlRow& p : points) {
    const size_t need = p.control ? 1 : 2;
    if (p.measurements.size() < need) {
      throw InputError(path, p.line,
                       std::string(p.control ? "control" : "check") + " point '" + p.name +
                           "' is measured in " + std::to_string(p.measurements.size()) +
                           " image(s); it needs at least " + std::to_string(need) +
                           (p.control ? "" : " (to be triangulated)"));
    }
  }
  return points;
}

}  // namespace dba
