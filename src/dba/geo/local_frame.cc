// CRS to geocentric through PROJ, and the local east-north-up frame; see
// local_frame.h.
#include "dba/geo/local_frame.h"


#include <cmath>
#include <numbers>
#include <stdexcept>

#include "dba/geo/proj_library.h"

namespace dba {
namespace {

// PROJ's reason for the context's last failure; "" when it gives none (a
// null char*, as for errno 0: never handed to std::string).
std::string ProjError(PJ_CONTEXT* ctx) {
  const ProjFunctions& api = Proj();
  const int error = api.proj_context_errno(ctx);
  const char* why = error == 0 ? nullptr : api.proj_context_errno_string(ctx, error);
  return why != nullptr ? why : "";
}

// The number of axes of a CRS (a compound CRS: its parts'), or 0.
int AxisCount(PJ_CONTEXT* ctx, PJ* crs) {
  const ProjFunctions& api = Proj();
  if (api.proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
    int n = 0;
    for (int i = 0; i < 2; ++i) {
      PJ* part = api.proj_crs_get_sub_crs(ctx, crs, i);
      if (part != nullptr) n += AxisCount(ctx, part), api.proj_destroy(part);
    }
    return n;
  }
  PJ* cs = api.proj_crs_get_coordinate_system(ctx, crs);
  if (cs == nullptr) return 0;
  const int n = api.proj_cs_get_axis_count(ctx, cs);
  api.proj_destroy(cs);
  return n;
}

}  // namespace

CrsToGeocentric::CrsToGeocentric(const std::string& crs) {
  const ProjFunctions& api = Proj();
  PJ_CONTEXT* ctx = api.proj_context_create();
  context_ = ctx;
  // PROJ's own log goes to stderr ("cart: Invalid latitude"); dba words
  // each failure itself, with PROJ's reason from the context's errno.
  api.proj_log_func(ctx, nullptr, [](void*, int, const char*) {});
  PJ* source = api.proj_create(ctx, crs.c_str());
  if (source == nullptr) {
    const std::string why = ProjError(ctx);
    api.proj_context_destroy(ctx);
    throw std::invalid_argument("PROJ cannot parse the CRS '" + crs + "'" +
                                (why.empty() ? "" : ": " + why));
  }
  if (!api.proj_is_crs(source)) {
    // A PROJ string without +type=crs ("+proj=geocent +ellps=WGS84") is a
    // coordinate operation to PROJ, whatever it names.
    api.proj_destroy(source);
    api.proj_context_destroy(ctx);
    throw std::invalid_argument(
        "PROJ takes '" + crs + "' as a coordinate operation, not a CRS: name a CRS (e.g. "
        "EPSG:4979, EPSG:4978), or end a PROJ string with +type=crs");
  }
  const int axes = AxisCount(ctx, source);
  height_kind_ = api.proj_get_type(source) == PJ_TYPE_COMPOUND_CRS ? "geoid/other" : "ellipsoidal";
  if (axes != 3) {
    api.proj_destroy(source);
    api.proj_context_destroy(ctx);
    throw std::invalid_argument("the CRS '" + crs + "' has " + std::to_string(axes) +
                                " axes: a 3D CRS is needed (with heights), e.g. EPSG:4979 "
                                "(WGS84 latitude, longitude, ellipsoidal height)");
  }
  PJ* target = api.proj_create(ctx, "EPSG:4978");
  PJ* t = api.proj_create_crs_to_crs_from_pj(ctx, source, target, nullptr, nullptr);
  api.proj_destroy(source);
  api.proj_destroy(target);
  if (t == nullptr) {
    const std::string why = ProjError(ctx);
    api.proj_context_destroy(ctx);
    throw std::invalid_argument("PROJ has no transformation from '" + crs +
                                "' to geocentric coordinates: " + why);
  }
  transform_ = t;
}

CrsToGeocentric::~CrsToGeocentric() {
  const ProjFunctions& api = Proj();
  api.proj_destroy(static_cast<PJ*>(transform_));
  api.proj_context_destroy(static_cast<PJ_CONTEXT*>(context_));
}

Eigen::Vector3d CrsToGeocentric::Forward(const Eigen::Vector3d& xyz) const {
  return Transform(xyz, true);
}

Eigen::Vector3d CrsToGeocentric::Inverse(const Eigen::Vector3d& ecef) const {
  return Transform(ecef, false);
}

Eigen::Vector3d CrsToGeocentric::Transform(const Eigen::Vector3d& xyz, bool forward) const {
  const ProjFunctions& api = Proj();
  PJ_COORD c = api.proj_coord(xyz.x(), xyz.y(), xyz.z(), 0.0);
  const PJ_COORD r = api.proj_trans(static_cast<PJ*>(transform_), forward ? PJ_FWD : PJ_INV, c);
  const Eigen::Vector3d out(r.xyz.x, r.xyz.y, r.xyz.z);
  if (!out.allFinite() || std::abs(out.x()) == HUGE_VAL) {
    throw std::runtime_error("PROJ cannot transform (" + std::to_string(xyz.x()) + ", " +
                             std::to_string(xyz.y()) + ", " + std::to_string(xyz.z()) +
                             (forward ? ") to" : ") from") +
                             " geocentric coordinates (outside the CRS's area, or a grid it "
                             "needs is missing)");
  }
  // A ballpark transformation takes geoid (or other) heights as
  // ellipsoidal ones, tens of metres off: the classic georeferencing
  // mistake, refused (PROJ picks it when the grid it needs is missing).
  PJ* used = api.proj_trans_get_last_used_operation(static_cast<PJ*>(transform_));
  const bool ballpark =
      used != nullptr && api.proj_coordoperation_has_ballpark_transformation(
                             static_cast<PJ_CONTEXT*>(context_), used) != 0;
  if (used != nullptr) api.proj_destroy(used);
  if (ballpark) {
    throw std::runtime_error(
        "PROJ has only a ballpark transformation to geocentric coordinates for this CRS (its "
        "heights are not ellipsoidal and the grid to convert them is missing): they would be "
        "taken as ellipsoidal heights, tens of metres off; install the grid (projsync, or "
        "PROJ_NETWORK=ON) or give ellipsoidal heights (e.g. EPSG:4979)");
  }
  return out;
}

std::string CrsToGeocentric::Pipeline() const {
  const ProjFunctions& api = Proj();
  const PJ_PROJ_INFO info = api.proj_pj_info(static_cast<PJ*>(transform_));
  return info.definition != nullptr ? info.definition : "";
}

Eigen::Vector3d GeocentricToGeodetic(const Eigen::Vector3d& p) {
  constexpr double a = 6378137.0, f = 1.0 / 298.257223563;
  constexpr double b = a * (1 - f), e2 = f * (2 - f), ep2 = e2 / (1 - e2);
  const double r = std::hypot(p.x(), p.y());
  const double theta = std::atan2(p.z() * a, r * b);
  const double st = std::sin(theta), ct = std::cos(theta);
  const double phi = std::atan2(p.z() + ep2 * b * st * st * st, r - e2 * a * ct * ct * ct);
  const double lambda = std::atan2(p.y(), p.x());
  const double N = a / std::sqrt(1 - e2 * std::sin(phi) * std::sin(phi));
  const double h = r / std::cos(phi) - N;
  constexpr double deg = 180.0 / std::numbers::pi;
  return Eigen::Vector3d(phi * deg, lambda * deg, h);
}

LocalFrame LocalFrame::At(const Eigen::Vector3d& origin_ecef) {
  LocalFrame f;
  f.origin = origin_ecef;
  f.origin_geodetic = GeocentricToGeodetic(origin_ecef);
  constexpr double rad = std::numbers::pi / 180.0;
  const double phi = f.origin_geodetic.x() * rad, lambda = f.origin_geodetic.y() * rad;
  const double sp = std::sin(phi), cp = std::cos(phi), sl = std::sin(lambda), cl = std::cos(lambda);
  f.R << -sl, cl, 0.0, -sp * cl, -sp * sl, cp, cp * cl, cp * sl, sp;
  return f;
}

}  // namespace dba
