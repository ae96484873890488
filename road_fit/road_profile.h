// The fitted ribbon sampled on a uniform arc-length grid: what road.h5 stores.
#pragma once

#include <vector>

#include "road_fit/ribbon_fit.h"

namespace ttz::road {

struct RoadProfile {
  double ds_m = 1.0;  // spacing = length / round(length / requested spacing), so the grid ends at the length
  bool closed = false;
  std::vector<double> s, x, y, z, theta, sigma, width;  // [m], [m], [m], [m], [rad], [rad], [m]
  std::vector<double> banking;                          // xi [rad]
  std::vector<double> kappa, nu, tau;                   // eq. 12 in our convention [1/m]
  double length() const { return s.back(); }
};

// Samples the ribbon every ~ds metres of s by integrating eq. 8 inside each interval from its
// first node under the interval's control (RK4), so the profile satisfies the ribbon's dynamics
// exactly between nodes and jumps at the nodes only by the collocation defects.
RoadProfile SampleRibbon(const Ribbon& ribbon, double ds_m);

// A ribbon whose nodes are the profile's samples (zeta = s, so u_s = 0) and whose controls are
// the differences of the sampled states: the next pass of the fit starts from it.
Ribbon RibbonFromProfile(const RoadProfile& profile);

}  // namespace ttz::road
