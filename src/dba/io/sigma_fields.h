// The σ fields of dba's own text inputs (camera priors, ground control):
// positive and within a physical range, refused with the file and line.
#pragma once

#include <cstdint>
#include <string>

namespace dba {

// σ of a surveyed position, in the coordinates' units (metres, or the
// CRS's): from a micrometre to a thousand kilometres.
inline constexpr double kMinSigma = 1e-6;
inline constexpr double kMaxSigma = 1e6;

// Throws InputError(path, line) unless both σ are within [kMinSigma,
// kMaxSigma]; `xy_field` and `z_field` are the fields as written.
void CheckSigmas(const std::string& path, int64_t line, double sigma_xy, double sigma_z,
                 const std::string& xy_field, const std::string& z_field);

}  // namespace dba
