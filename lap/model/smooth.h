// Smooth (C-infinity) positive and negative parts, replacing the kinked f+ and f- of the paper's
// eq. 17, 18 and 25: an optimal-control solver with Newton steps needs C2 functions.
//
//   f+(x) = (x + sqrt(x^2 + d^2)) / 2,   f-(x) = (x - sqrt(x^2 + d^2)) / 2 = x - f+(x)
//
// d is the smoothing width, in the unit of x. f+(x) + f-(x) = x exactly (so tau_t + tau_b = tau_w
// holds exactly); 0 < f+(x) - max(x, 0) <= d/2, falling as d^2 / (4 |x|) for |x| >> d.
#pragma once

#include <cmath>

#include "lap/model/scalar.h"

namespace ttz::lap {

// Smoothing widths of the model, each in the unit of the smoothed quantity.
struct Smoothing {
  // Wheel torque split tau_w -> (tau_t, tau_b), eq. 17 [N m]; the torques in use are +-1000 N m.
  double torque = 2.0;
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

// f-(x) of width d > 0 [unit of x]; f-(x) = x - f+(x) <= 0.
template <typename T>
T SmoothNegative(const T& x, double d) {
  using std::sqrt;
  return (x - sqrt(x * x + d * d)) * 0.5;
}

}  // namespace ttz::lap
