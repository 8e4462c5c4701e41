// WGS84 -> geocentric through PROJ against PROJ's own cs2cs at fixed points
// (cs2cs -f %.6f EPSG:4979 EPSG:4978, values checked in below), the
// geocentric -> geodetic closed form, and the local east-north-up frame.
#include "dba/geo/local_frame.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace dba {
namespace {

struct Fixed {
  Eigen::Vector3d lat_lon_h, ecef;
};
// echo "LAT LON H" | cs2cs -f "%.6f" EPSG:4979 EPSG:4978 (PROJ 9.1.1)
const Fixed kFixed[] = {
    {{49.0, 8.0, 200}, {4151764.384704, 583492.432114, 4790709.689388}},
    {{-33.8688, 151.2093, 58.5}, {-4646093.841126, 2553229.735762, -3534404.989557}},
    {{64.1466, -21.9426, 10}, {2586857.950897, -1042145.070410, 5716869.322747}},
    {{0.5, -78.5, 2850}, {1272116.081732, -6252650.303463, 55311.320906}},
    {{47.3769, 8.5417, 408}, {4279227.806486, 642719.222147, 4670540.878541}},
};

TEST(LocalFrame, Wgs84ToGeocentricMatchesCs2cs) {
  const CrsToGeocentric wgs84("EPSG:4979");  // latitude, longitude, height (EPSG's order)
  EXPECT_EQ(wgs84.HeightKind(), "ellipsoidal");
  EXPECT_FALSE(wgs84.Pipeline().empty());
  for (const Fixed& f : kFixed) {
    EXPECT_LT((wgs84.Forward(f.lat_lon_h) - f.ecef).norm(), 2e-6) << f.lat_lon_h.transpose();
    const Eigen::Vector3d back = GeocentricToGeodetic(f.ecef);
    EXPECT_NEAR(back.x(), f.lat_lon_h.x(), 1e-8);
    EXPECT_NEAR(back.y(), f.lat_lon_h.y(), 1e-8);
    EXPECT_NEAR(back.z(), f.lat_lon_h.z(), 1e-3);
  }
}

TEST(LocalFrame, EastNorthUpAtTheOrigin) {
  const CrsToGeocentric wgs84("EPSG:4979");
  const Eigen::Vector3d o(47.3769, 8.5417, 408);
  const LocalFrame frame = LocalFrame::At(wgs84.Forward(o));
  EXPECT_NEAR(frame.origin_geodetic.x(), o.x(), 1e-8);
  EXPECT_LT((frame.R * frame.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // 100 m straight up, and a little north and east.
  EXPECT_LT((frame.ToLocal(wgs84.Forward(o + Eigen::Vector3d(0, 0, 100))) -
             Eigen::Vector3d(0, 0, 100)).norm(), 1e-6);
  const Eigen::Vector3d north = frame.ToLocal(wgs84.Forward(o + Eigen::Vector3d(1e-3, 0, 0)));
  EXPECT_GT(north.y(), 110.0);  // 0.001° of latitude ≈ 111 m
  EXPECT_LT(std::abs(north.x()), 1e-6);
  const Eigen::Vector3d east = frame.ToLocal(wgs84.Forward(o + Eigen::Vector3d(0, 1e-3, 0)));
  EXPECT_GT(east.x(), 70.0);  // cos 47.4° · 111 m
  EXPECT_LT(std::abs(east.y()), 1e-3);
  // And back.
  const Eigen::Vector3d x(123.4, -56.7, 8.9);
  EXPECT_LT((frame.ToLocal(frame.ToGeocentric(x)) - x).norm(), 1e-9);
}

// Geoid heights: converted through the geoid grid where PROJ has it
// (EGM96, in Debian's proj-data; cs2cs -f "%.6f" EPSG:4326+5773 EPSG:4978),
// refused where it would only have a ballpark transformation (EGM2008,
// whose grid proj-data does not ship), which would take them as
// ellipsoidal heights.
TEST(LocalFrame, GeoidHeightsThroughTheirGridAndNeverBallpark) {
  const CrsToGeocentric egm96("EPSG:4326+5773");
  EXPECT_EQ(egm96.HeightKind(), "geoid/other");
  const Eigen::Vector3d p(52.0, 5.0, 10.0);
  const Eigen::Vector3d ecef = egm96.Forward(p);
  EXPECT_LT((ecef - Eigen::Vector3d(3920019.516386, 342957.268484, 5002845.439474)).norm(), 1e-3);
  EXPECT_GT((ecef - CrsToGeocentric("EPSG:4979").Forward(p)).norm(), 30.0);  // the undulation
  const CrsToGeocentric egm2008("EPSG:4326+3855");
  try {
    egm2008.Forward(p);
    ADD_FAILURE() << "a ballpark height transformation was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("only a ballpark transformation"), std::string::npos)
        << e.what();
  }
}

TEST(LocalFrame, RefusesWhatPROJCannotParseAnd2dCrs) {
  try {
    CrsToGeocentric bad("EPSG:NOPE");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("PROJ cannot parse the CRS 'EPSG:NOPE'"), std::string::npos)
        << e.what();
  }
  try {
    CrsToGeocentric flat("EPSG:4326");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("has 2 axes: a 3D CRS is needed"), std::string::npos)
        << e.what();
  }
}

// A PROJ string without +type=crs parses as a coordinate operation, with no
// error number: named as such (PROJ's null reason once reached std::string,
// "basic_string: construction from null is not valid"); with +type=crs it
// is the geocentric CRS.
TEST(LocalFrame, AProjOperationIsRefusedAsNotACrs) {
  try {
    CrsToGeocentric operation("+proj=geocent +ellps=WGS84");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "PROJ takes '+proj=geocent +ellps=WGS84' as a coordinate operation, not a CRS: "
                 "name a CRS (e.g. EPSG:4979, EPSG:4978), or end a PROJ string with +type=crs");
  }
  const CrsToGeocentric crs("+proj=geocent +datum=WGS84 +type=crs");
  const Eigen::Vector3d x(4193000.0, 815000.0, 4717000.0);
  EXPECT_LT((crs.Forward(x) - x).norm(), 1e-6);
}

}  // namespace
}  // namespace dba
