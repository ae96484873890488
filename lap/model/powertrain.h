// Brushed-DC power train: battery (eq. 22), controller (eq. 23), motor (eq. 24-26, 30-31), heat
// balance (eq. 27-29), battery current (eq. 32) and discharge (eq. 33). The `count` motors act as
// one equivalent motor (bike.h, MotorsInParallel).
//
// Decisions (see docs/lap.md):
// - Eq. 32 is garbled in the paper (an undefined eta_m); it is the smaller root of eq. 22-23,
//   R_b i_b^2 - V_bn i_b + P_m / eta_mc = 0 with P_m = V_mm i_m, written in the form
//   i_b = 2 c / (V_bn + sqrt(V_bn^2 - 4 R_b c)), c = P_m / eta_mc, which stays exact as R_b -> 0.
// - Eq. 25 (tau_e = k_tau f+(i_m - i_m0)): i_m0 is the no-load current, the motor's own friction
//   and iron loss k_tau i_m0, which the controller must cover before the shaft gives torque. The
//   controller never regenerates, so i_m = f+(tau_demand / k_tau + i_m0) >= 0 and the shaft
//   torque is tau_e = k_tau (i_m - i_m0): eq. 25 while driving, and a friction drag down to
//   -k_tau i_m0 when the current is cut. This keeps i_m convex in the wheel torque, so the
//   Hamiltonian has one minimum in tau_w; a current that jumps by i_m0 as soon as the motor drives
//   (the paper's literal reading) gave H two minima, coasting and driving, and the per-node control
//   elimination jumped between them (docs/lap.md).
#pragma once

#include <cmath>

#include "lap/model/scalar.h"
#include "lap/model/smooth.h"
#include "lap/model/vehicle.h"

namespace ttz::lap {

template <typename T>
struct Powertrain {
  T tau_t, tau_b;   // motor and brake torque at the wheel [N m] (eq. 17), tau_t + tau_b = tau_w
  T omega_m;        // motor speed gamma_c omega_w [rad/s]
  T tau_e;          // motor shaft torque k_tau (i_m - i_m0) [N m] (eq. 25, 31)
  T R_m, k_V, k_tau;  // at temperature T (eq. 26) [ohm], [V s/rad], [N m/A]
  T i_m;            // motor current [A] (eq. 25)
  T V_mm;           // motor voltage [V] (eq. 24, 30)
  T P_m;            // electric power into the motor V_mm i_m [W]
  T V_bn;           // open-circuit voltage of the pack [V] (eq. 22b)
  T i_b;            // battery current [A] (eq. 32)
  T V_mb;           // pack terminal voltage V_bn - i_b R_b [V] (eq. 22a)
  T P_b;            // power drawn from the ideal source V_bn i_b [W] (eq. 33, 39f)
  T Q_in, Q_out;    // heat into and out of the motor [W] (eq. 28)
  T T_dot;          // motor temperature rate [K/s] (eq. 27)
  T e_dot;          // battery energy rate -V_bn i_b [W] (eq. 33)
};

template <typename T>
Powertrain<T> ComputePowertrain(const Vehicle& v, const T& tau_w, const T& omega_w, const T& V,
                                const T& temperature, const T& e) {
  using std::sqrt;
  const EquivalentMotor& m = v.motor;
  Powertrain<T> p;
  p.omega_m = omega_w * v.gamma_c;
  const T dT = temperature - m.T_0;
  p.R_m = m.R_m0 + m.sigma_R * dT;                                        // eq. 26
  p.k_V = m.k_V0 - m.sigma_m * dT;
  p.k_tau = m.k_tau0 - m.sigma_m * dT;
  const double drive = v.eta_c * v.gamma_c;                               // eq. 31
  p.i_m = SmoothPositive(tau_w / (drive * p.k_tau) + m.i_m0, v.smoothing.current);  // eq. 25
  p.tau_e = p.k_tau * (p.i_m - m.i_m0);                                   // eq. 25
  p.tau_t = drive * p.tau_e;                                              // eq. 31
  p.tau_b = tau_w - p.tau_t;                                              // eq. 17
  p.V_mm = p.k_V * p.omega_m + p.R_m * p.i_m;                             // eq. 24, 30
  p.P_m = p.V_mm * p.i_m;
  p.V_bn = v.pack.V_bn0 + (v.pack.V_bn1 - v.pack.V_bn0) * e / v.pack.e_i;  // eq. 22b
  const T c = p.P_m / v.eta_mc;                                           // eq. 23
  const T disc = p.V_bn * p.V_bn - 4.0 * v.pack.R_b * c;
  const double d = v.smoothing.discriminant * v.pack.V_bn1 * v.pack.V_bn1;
  p.i_b = 2.0 * c / (p.V_bn + sqrt(SmoothPositive(disc, d)));             // eq. 32
  p.V_mb = p.V_bn - p.i_b * v.pack.R_b;                                   // eq. 22a
  p.P_b = p.V_bn * p.i_b;
  p.Q_in = p.P_m - p.omega_m * p.tau_e;                                   // eq. 28
  const T q = m.q_0 + (m.q_1 - m.q_0) / m.V_1 * V;                        // eq. 29
  p.Q_out = q * (temperature - v.T_ext);
  p.T_dot = (p.Q_in - p.Q_out) / m.C;                                     // eq. 27
  p.e_dot = -p.P_b;                                                       // eq. 33
  return p;
}

}  // namespace ttz::lap
