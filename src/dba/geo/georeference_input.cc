// Georeferencing input matched to a problem's images; see georeference_input.h.
#include "dba/geo/georeference_input.h"

#include <cstdio>

#include "dba/common/error.h"
#include "dba/io/camera_priors_file.h"
#include "dba/io/ground_control_file.h"
#include "dba/io/text_tokens.h"

namespace dba {

std::optional<int32_t> ResolveImage(const std::string& path, int64_t line, const std::string& image,
                                    const ImageNames& names, int64_t num_images) {
  if (!names.problem.empty()) {
    const auto it = names.index.find(image);
    if (it != names.index.end()) return it->second;
    if (names.others.contains(image)) return std::nullopt;  // not adjusted
    throw InputError(path, line, "unknown image '" + Clipped(image) + "' (not in the COLMAP model)");
  }
  int64_t i = -1;
  if (ParseInteger(image, &i) != NumberStatus::kOk || i < 0 || i >= num_images) {
    throw InputError(path, line,
                     "image '" + Clipped(image) + "': expected a 0-based camera index below " +
                         std::to_string(num_images) + " (BAL and .dba problems have no names)");
  }
  return static_cast<int32_t>(i);
}

CameraPriors LoadCameraPriors(const std::string& path, const ImageNames& names,
                              int64_t num_images, const std::optional<Eigen::Vector2d>& default_sigma,
                              const RobustLoss& loss) {
  CameraPriors priors;
  priors.loss = loss;
  for (const CameraPriorRow& row : ReadCameraPriorsFile(path)) {
    CameraCentrePrior p;
    const std::optional<int32_t> image = ResolveImage(path, row.line, row.image, names, num_images);
    if (!image) continue;
    p.image = *image;
    const std::optional<Eigen::Vector2d> sigma = row.sigma ? row.sigma : default_sigma;
    if (!sigma) {
      throw InputError(path, row.line, "no SIGMA_XY SIGMA_Z on the line and no --prior-sigma XY,Z");
    }
    p.centre = row.xyz;
    p.sigma = Vec3((*sigma)[0], (*sigma)[0], (*sigma)[1]);
    priors.priors.push_back(p);
  }
  return priors;
}

GroundControl LoadGroundControl(const std::string& path, const ImageNames& names,
                                int64_t num_images) {
  GroundControl gcps;
  for (const GroundControlRow& row : ReadGroundControlFile(path)) {
    GroundControlPoint p;
    p.name = row.name;
    p.position = row.xyz;
    p.sigma = Vec3(row.sigma[0], row.sigma[0], row.sigma[1]);
    p.control = row.control;
    for (const GroundControlMeasurementRow& m : row.measurements) {
      const std::optional<int32_t> image = ResolveImage(path, m.line, m.image, names, num_images);
      if (!image) continue;
      if (!names.size.empty()) {
        const auto [w, h] = names.size[*image];
        if (!(m.pixel.x() >= 0 && m.pixel.x() <= static_cast<double>(w) && m.pixel.y() >= 0 &&
              m.pixel.y() <= static_cast<double>(h))) {
          char where[160];
          std::snprintf(where, sizeof where, "(%g, %g) is outside image '%s' (%llu x %llu pixels)",
                        m.pixel.x(), m.pixel.y(), m.image.c_str(),
                        static_cast<unsigned long long>(w), static_cast<unsigned long long>(h));
          throw InputError(path, m.line, "measurement of '" + row.name + "': " + where);
        }
      }
      p.measurements.push_back({*image, m.pixel});
    }
    if (p.measurements.size() < (p.control ? 1u : 2u)) {
      throw InputError(path, row.line, "point '" + row.name + "' is measured in too few of the "
                                       "adjusted images (" + std::to_string(p.measurements.size()) + ")");
    }
    gcps.points.push_back(std::move(p));
  }
  return gcps;
}

}  // namespace dba
