// Synthetic roads for the lap tests: a road.h5 (common/road_artefact.h) sampled every metre from
// its curvature, slope and width along s.
#pragma once

#include <cmath>
#include <functional>

#include "common/road_artefact.h"

namespace ttz::lap::testing {

using Profile = std::function<double(double)>;  // a function of s [m]
inline double Zero(double) { return 0.0; }

// Heading rate kappa(s) = cos(sigma) dtheta/ds [1/m] (left positive), slope sigma(s) [rad],
// width [m] and banking xi(s) [rad] (left border higher positive), with the road frame's
// curvatures of eq. 12 that go with them (road_fit/ribbon.h, docs/road_h5.md): road.h5's kappa
// cos(xi) kappa + sin(xi) sigma', nu = cos(xi) sigma' - sin(xi) kappa and the torsion
// tan(sigma) kappa + xi'. Without banking, road.h5's kappa is the given one.
inline RoadArtefact SyntheticRoad(double length, const Profile& width, const Profile& kappa,
                                  const Profile& sigma, const Profile& banking = Zero) {
  RoadArtefact r;
  for (int i = 0; i <= static_cast<int>(length); ++i) {
    const double s = i, turn = kappa(s), xi = banking(s);
    const double sigma_rate = sigma(s + 0.5) - sigma(s - 0.5), xi_rate = banking(s + 0.5) - banking(s - 0.5);
    r.s.push_back(s);
    r.kappa.push_back(std::cos(xi) * turn + std::sin(xi) * sigma_rate);
    r.sigma.push_back(sigma(s));
    r.banking.push_back(xi);
    r.nu.push_back(std::cos(xi) * sigma_rate - std::sin(xi) * turn);
    r.tau.push_back(std::tan(sigma(s)) * turn + xi_rate);
    r.width.push_back(width(s));
  }
  return r;
}

inline RoadArtefact SyntheticRoad(double length, double width, const Profile& kappa,
                                  const Profile& sigma, const Profile& banking = Zero) {
  return SyntheticRoad(length, [width](double) { return width; }, kappa, sigma, banking);
}

// A straight, level road 8 m wide.
inline RoadArtefact StraightRoad(double length) { return SyntheticRoad(length, 8.0, Zero, Zero); }

}  // namespace ttz::lap::testing
