// Linear tyre limited by the adherence ellipse (eq. 17-20) and the traction/braking split (eq. 17).
//
// Decisions (see docs/lap.md):
// - Table A1 gives r = 0.1 m and r_t = 0.3 m; a 0.1 m wheel with a 0.3 m tyre section is not a
//   motorcycle, and eq. 16 and 20 need r > r_t for a positive rolling radius: bike.yaml holds the
//   physical r = 0.3 m, r_t = 0.1 m (bike.cc rejects r_t >= r).
// - Eq. 18 gives the rolling-resistance "torque" as (N cos(phi) + F_y sin(phi)) mu_r, a force; it is
//   multiplied by the rolling radius R_e (below) to be a torque, so mu_r keeps its usual meaning
//   (resistance force / load, 0.015).
#pragma once

#include <cmath>

#include "lap/model/scalar.h"
#include "lap/model/smooth.h"
#include "lap/model/vehicle.h"

namespace ttz::lap {

template <typename T>
struct TyreForces {
  T R_e;      // rolling radius r - r_t (1 - cos(phi)) - z cos(phi) [m] (eq. 16, 20)
  T kappa_w;  // longitudinal slip [1] (eq. 20)
  T N;        // load [N] (eq. 18)
  T F_x, F_y; // longitudinal and lateral force [N] (eq. 18)
  T tau_r;    // rolling-resistance torque [N m] (eq. 18, times R_e)
  T ellipse;  // (F_x / (N mu_x))^2 + (F_y / (N mu_y))^2 [1] (eq. 19), <= 1
};

template <typename T>
TyreForces<T> ComputeTyre(const Vehicle& v, const T& V, const T& beta, const T& z, const T& phi,
                          const T& omega_w, const T& z_dot) {
  using std::cos;
  using std::sin;
  TyreForces<T> t;
  const T cp = cos(phi);
  t.R_e = v.r - v.r_t + cp * (v.r_t - z);                              // eq. 20's bracket
  t.kappa_w = (omega_w * t.R_e - V) / V;                               // eq. 20
  t.N = SmoothPositive(v.K_s * z + v.K_c * z_dot, v.smoothing.load);   // eq. 18
  const T cx = v.K_kappa * t.kappa_w;                                  // F_x / N
  const T cy = v.K_beta * beta + v.K_phi * phi;                        // F_y / N
  t.F_x = t.N * cx;
  t.F_y = t.N * cy;
  t.tau_r = (t.N * cp + t.F_y * sin(phi)) * v.mu_r * t.R_e;
  t.ellipse = (cx / v.mu_x) * (cx / v.mu_x) + (cy / v.mu_y) * (cy / v.mu_y);  // eq. 19
  return t;
}

// Aerodynamic drag D and lift L (eq. 21) [N].
template <typename T>
void ComputeAero(const Vehicle& v, const T& V, T* D, T* L) {
  *D = v.drag_k * V * V;
  *L = v.lift_k * V * V;
}

}  // namespace ttz::lap
