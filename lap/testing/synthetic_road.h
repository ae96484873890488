// Synthetic roads for the lap tests: a road.h5 (common/road_artefact.h) sampled every metre from
// its curvature, slope and width along s.
#pragma once

#include <cmath>
#include <functional>

#include "common/road_artefact.h"

namespace ttz::lap::testing {

using Profile = std::function<double(double)>;  // a function of s [m]
inline double Zero(double) { return 0.0; }

// Curvature kappa(s) [1/m] in road.h5's sign (left positive), slope sigma(s) [rad] and width [m],
// with the vertical curvature nu = dsigma/ds and the torsion tau = tan(sigma) kappa that go with
// them (eq. 12; docs/road_h5.md).
inline RoadArtefact SyntheticRoad(double length, const Profile& width, const Profile& kappa,
                                  const Profile& sigma) {
  RoadArtefact r;
  for (int i = 0; i <= static_cast<int>(length); ++i) {
    const double s = i;
    r.s.push_back(s);
    r.kappa.push_back(kappa(s));
    r.sigma.push_back(sigma(s));
    r.nu.push_back(sigma(s + 0.5) - sigma(s - 0.5));
    r.tau.push_back(std::tan(sigma(s)) * kappa(s));
    r.width.push_back(width(s));
  }
  return r;
}

inline RoadArtefact SyntheticRoad(double length, double width, const Profile& kappa,
                                  const Profile& sigma) {
  return SyntheticRoad(length, [width](double) { return width; }, kappa, sigma);
}

// A straight, level road 8 m wide.
inline RoadArtefact StraightRoad(double length) { return SyntheticRoad(length, 8.0, Zero, Zero); }

}  // namespace ttz::lap::testing
