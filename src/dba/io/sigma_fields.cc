// The σ range of dba's own text inputs; see sigma_fields.h.
#include "dba/io/sigma_fields.h"

#include "dba/common/error.h"

namespace dba {

void CheckSigmas(const std::string& path, int64_t line, double sigma_xy, double sigma_z,
                 const std::string& xy_field, const std::string& z_field) {
  auto fits = [](double s) { return s >= kMinSigma && s <= kMaxSigma; };
  if (fits(sigma_xy) && fits(sigma_z)) return;
  throw InputError(path, line,
                   "sigma must be within [1e-06, 1e+06] (the coordinates' units), got SIGMA_XY " +
                       xy_field + " and SIGMA_Z " + z_field);
}

}  // namespace dba
