#include "common/geodesy.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ttz {
namespace {

const LatLon kDouglas{54.1667, -4.4806};

TEST(Geodesy, OriginMapsToZeroAndRoundTrips) {
  const LocalFrame f = LocalFrame::CentredOn(kDouglas);
  const EastNorth o = f.Forward(kDouglas);
  EXPECT_NEAR(o.x_m, 0.0, 1e-6);
  EXPECT_NEAR(o.y_m, 0.0, 1e-6);
  const LatLon p{54.31, -4.38};
  const LatLon back = f.Inverse(f.Forward(p));
  EXPECT_NEAR(back.lat_deg, p.lat_deg, 1e-9);
  EXPECT_NEAR(back.lon_deg, p.lon_deg, 1e-9);
}

TEST(Geodesy, EastIsXNorthIsYAndLengthsAreTrue) {
  const LocalFrame f = LocalFrame::CentredOn(kDouglas);
  const EastNorth east = f.Forward({kDouglas.lat_deg, kDouglas.lon_deg + 0.01});
  const EastNorth north = f.Forward({kDouglas.lat_deg + 0.01, kDouglas.lon_deg});
  EXPECT_GT(east.x_m, 0);
  EXPECT_GT(north.y_m, 0);
  // One hundredth of a degree of latitude at 54.17 N on WGS84: meridian arc 1113.1 m
  // (M = a (1 - e^2) / (1 - e^2 sin^2 phi)^1.5 = 6,377,4xx m).
  const double phi = kDouglas.lat_deg * M_PI / 180, e2 = 0.00669437999014, a = 6378137.0;
  const double meridian = a * (1 - e2) / std::pow(1 - e2 * std::sin(phi) * std::sin(phi), 1.5);
  EXPECT_NEAR(std::hypot(north.x_m, north.y_m) / (meridian * 0.01 * M_PI / 180), 1.0, 1e-4);
}

TEST(Geodesy, RecreatedFromItsProjStringMapsTheSame) {
  const LocalFrame f = LocalFrame::CentredOn(kDouglas);
  const LocalFrame g = LocalFrame::FromProjString(f.ProjString());
  const LatLon p{54.25, -4.5};
  EXPECT_NEAR(f.Forward(p).x_m, g.Forward(p).x_m, 1e-9);
  EXPECT_NEAR(g.Origin().lat_deg, kDouglas.lat_deg, 1e-9);
  EXPECT_NE(f.Wkt().find("Transverse Mercator"), std::string::npos);
}

}  // namespace
}  // namespace ttz
