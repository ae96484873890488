// The motorcycle as the model sees it: every constant of eq. 9-39 in SI units, derived once from
// the bike.yaml parameters (lap/bike.h). Model code reads only this struct.
#pragma once

#include "lap/bike.h"
#include "lap/model/smooth.h"

namespace ttz::lap {

struct Vehicle {
  // Chassis and rider (eq. 13-16, Table A1).
  double M;         // total mass [kg] (TotalMass: base + motors + pack)
  double h;         // centre-of-mass height [m]
  double I_xx, I_yy, I_zz, I_gy, I_wy;  // [kg m^2]
  // Tyre (eq. 18-20).
  double r, r_t;    // wheel radius and toroid radius [m]
  double K_kappa, K_beta, K_phi;  // [1], [1/rad], [1/rad]
  double K_s, K_c;  // radial stiffness [N/m] and damping [N s/m]
  double mu_x, mu_y, mu_r;        // [1]
  // Aerodynamics (eq. 21): 0.5 rho C_d and 0.5 rho C_l [kg/m].
  double drag_k, lift_k;
  // Equivalent motor of the `count` motors in parallel (eq. 24-29; see bike.h).
  EquivalentMotor motor;
  double eta_mc;    // controller efficiency [1] (eq. 23)
  // Battery pack (eq. 22, 33).
  PackFigures pack;
  double P_b_max;   // [W] (eq. 39f)
  // Drive (eq. 31).
  double gamma_c, eta_c;  // [1]
  // Environment.
  double g;         // [m/s^2]
  double T_ext;     // [degC]
  // Limits (eq. 39a-c) and the brake (control bound, see constraints.h).
  double omega_phi_max, Omega_z_max;  // [rad/s]
  double border_margin;               // [m]
  double brake_torque_max;            // [N m] at the wheel
  double yaw_accel_weight;            // c_y [s^4/rad^2] (cost.h)
  double torque_rate_weight;          // c_t [s^3/(N m)^2] (cost.h)
  double roll_rate_weight;            // c_r [s^2/rad^2] (cost.h)
  // Initial state.
  double V0, T0, e0;  // [m/s], [degC], [J]
  // Smoothing widths of f+ / f- (smooth.h).
  Smoothing smoothing;
};

Vehicle MakeVehicle(const BikeParams& p);

}  // namespace ttz::lap
