// A smooth (C-infinity) positive part, replacing the kinked f+ of the paper's eq. 18 and 25: an
// optimal-control solver with Newton steps needs C2 functions.
//
//   f+(x) = (x + sqrt(x^2 + d^2)) / 2
//
// d is the smoothing width, in the unit of x; 0 < f+(x) - max(x, 0) <= d/2, falling as
// d^2 / (4 |x|) for |x| >> d. f+ is convex, so a convex argument keeps it convex.
#pragma once

#include <cmath>

#include "lap/model/scalar.h"

namespace ttz::lap {

// Smoothing widths of the model, each in the unit of the smoothed quantity.
struct Smoothing {
  // Motor current i_m = f+(demand + i_m0), eq. 25 [A]: the currents in use reach 1200 A; the
  // bias at zero demand is d^2 / (4 i_m0) = 0.06 A.
  double current = 2.0;
  // Tyre load N = f+(K_s z + K_c z_dot), eq. 18 [N]; bias d^2/(4 N) = 0.01 N at the static load.
  double load = 10.0;
  // Discriminant of the battery-current quadratic (powertrain.h) relative to V_bn^2 [1]: only
  // beyond the pack's maximum-power point does it act, keeping i_b finite there.
  double discriminant = 1e-3;
};

// f+(x) of width d > 0 [unit of x].
template <typename T>
T SmoothPositive(const T& x, double d) {
  using std::sqrt;
  return (x + sqrt(x * x + d * d)) * 0.5;
}

}  // namespace ttz::lap
