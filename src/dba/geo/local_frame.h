// Coordinates of a georeferenced solve. dba solves in a truly Cartesian
// local frame: east, north, up at an origin, through geocentric (ECEF,
// EPSG:4978) coordinates; never in projected coordinates plus height, which
// errs by d²/2R (about 0.3 m at the corners of a 10,000-image block).
//
//   local = R (X - X₀),  R's rows e, n, u at the origin's geodetic latitude
//   φ and longitude λ (WGS84):
//     e = (-sin λ, cos λ, 0)
//     n = (-sin φ cos λ, -sin φ sin λ, cos φ)
//     u = (cos φ cos λ, cos φ sin λ, sin φ)
//
// Any 3D CRS PROJ understands reaches geocentric coordinates through PROJ
// (Debian's libproj-dev), in the CRS's own axis order (EPSG:4979: latitude,
// longitude in degrees, ellipsoidal height in metres).
//
// Thread safety: a CrsToGeocentric is one thread's (PROJ context inside).
#pragma once

#include <Eigen/Core>
#include <string>

namespace dba {

// PROJ's transformation from a 3D CRS to EPSG:4978.
class CrsToGeocentric {
 public:
  // Throws std::invalid_argument when PROJ cannot parse `crs`, when it is
  // not 3D (a 2D CRS has no heights), or no transformation exists.
  explicit CrsToGeocentric(const std::string& crs);
  ~CrsToGeocentric();
  CrsToGeocentric(const CrsToGeocentric&) = delete;
  CrsToGeocentric& operator=(const CrsToGeocentric&) = delete;

  // Throws std::runtime_error when PROJ cannot transform the point (outside
  // the CRS's area, or a grid it needs is missing), or can only with a
  // ballpark transformation (geoid heights without their grid would be
  // taken as ellipsoidal ones).
  Eigen::Vector3d Forward(const Eigen::Vector3d& xyz) const;
  // Geocentric coordinates back into the CRS (the same refusals).
  Eigen::Vector3d Inverse(const Eigen::Vector3d& ecef) const;
  // The PROJ pipeline used (for the report).
  std::string Pipeline() const;
  // "ellipsoidal" or "geoid/other" heights, as PROJ names the vertical axis.
  std::string HeightKind() const { return height_kind_; }

 private:
  Eigen::Vector3d Transform(const Eigen::Vector3d& xyz, bool forward) const;
  void* context_ = nullptr;
  void* transform_ = nullptr;
  std::string height_kind_;
};

// Geodetic latitude, longitude (degrees) and ellipsoidal height (m) of a
// geocentric point on WGS84 (Bowring's closed form, below 1 mm on Earth).
Eigen::Vector3d GeocentricToGeodetic(const Eigen::Vector3d& ecef);

struct LocalFrame {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // ECEF
  Eigen::Vector3d origin_geodetic = Eigen::Vector3d::Zero();  // φ, λ (deg), h
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();   // rows e, n, u

  // The ENU frame at a geocentric origin.
  static LocalFrame At(const Eigen::Vector3d& origin_ecef);
  Eigen::Vector3d ToLocal(const Eigen::Vector3d& ecef) const { return R * (ecef - origin); }
  Eigen::Vector3d ToGeocentric(const Eigen::Vector3d& local) const {
    return R.transpose() * local + origin;
  }
};

}  // namespace dba
