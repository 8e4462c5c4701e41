// Georeferencing input matched to a problem's images: camera priors
// (io/camera_priors_file.h) and ground control (io/ground_control_file.h)
// read from their files, each image named resolved against the problem's
// (a COLMAP input's names, else 0-based indices).
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>

#include "dba/geo/ground_control.h"
#include "dba/io/image_names.h"
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

// An image named in `path` at `line`: by name when names.problem is not
// empty (a COLMAP input; nullopt for a name in names.others, an image of
// the model without observations to adjust), else a 0-based index below
// num_images. Throws InputError(path, line, ...) otherwise.
std::optional<int32_t> ResolveImage(const std::string& path, int64_t line, const std::string& image,
                                    const ImageNames& names, int64_t num_images);

// --gcps (io/ground_control_file.h): the points with their measurements in
// the problem's images (ResolveImage; measurements in images not adjusted
// are left out); for a COLMAP input a measurement outside its image (the
// only format with image sizes) is refused. The coordinates as read.
GroundControl LoadGroundControl(const std::string& path, const ImageNames& names,
                                int64_t num_images);

// --camera-priors (io/camera_priors_file.h): the rows of `path` matched to
// the problem's images, by name when names.problem is not empty (a COLMAP
// input; a name in names.others, an image of the model without observations
// to adjust, is skipped), else by 0-based index below num_images. Rows without σ take `default_sigma` (--prior-sigma XY,Z).
// Throws InputError(path, line, ...) for an unknown image, an index out of
// range, or no σ at all.
CameraPriors LoadCameraPriors(const std::string& path, const ImageNames& names,
                              int64_t num_images, const std::optional<Eigen::Vector2d>& default_sigma,
                              const RobustLoss& loss);

}  // namespace dba
