// The channels lap.h5 reports besides the states and controls: per mesh node, what the model
// (lap/model/dynamics.h, constraints.h) says about an optimal lap — accelerations, tyre forces,
// power train, energy, efficiencies, constraint values — and the lap's headline figures.
// Physics only: lap/lap_artefact.h writes them, docs/lap_h5.md documents them.
//
// Frame: the model's (lap/model/state.h): x forward, y right, z down.
#pragma once

#include <array>
#include <vector>

#include "lap/model/constraints.h"
#include "lap/model/vehicle.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

// The lap's headline figures.
struct LapFigures {
  double lap_time = 0.0;         // t at the last node [s]
  double energy_used = 0.0;      // e(0) - e(s_f) [J] (eq. 33)
  double energy_fraction = 0.0;  // energy_used / e_i, of the full pack [1]
  double top_speed = 0.0;        // max V [m/s]
  double start_speed = 0.0;      // V at the first node [m/s] (standing or flying: lap --start)
  double average_speed = 0.0;    // road length / lap time [m/s]
};

// One value per mesh node in each vector.
struct LapChannels {
  std::vector<double> sdot;             // ds/dt [m/s] (eq. 10a)
  std::vector<double> accel_long;       // dV/dt [m/s^2] (eq. 13-16 solved for the accelerations)
  std::vector<double> accel_lat;        // V Omega_z [m/s^2], right positive (see lap_channels.cc)
  std::vector<double> tyre_load;        // N [N] (eq. 18)
  std::vector<double> tyre_force_x;     // F_x [N], forward positive (eq. 18)
  std::vector<double> tyre_force_y;     // F_y [N], right positive (eq. 18)
  std::vector<double> ellipse_usage;    // (F_x/(N mu_x))^2 + (F_y/(N mu_y))^2 [1] (eq. 19)
  std::vector<double> tyre_slip;        // kappa_w [1] (eq. 20)
  std::vector<double> aero_drag;        // D [N] (eq. 21)
  std::vector<double> motor_torque;     // tau_e = k_tau (i_m - i_m0), all motors [N m] (eq. 25, 31)
  std::vector<double> motor_speed;      // omega_m = gamma_c omega_w [rad/s]
  std::vector<double> motor_current;    // i_m, all motors [A] (eq. 25)
  std::vector<double> motor_voltage;    // V_mm [V] (eq. 24, 30)
  std::vector<double> motor_power;      // V_mm i_m, electric power into the motors [W]
  std::vector<double> wheel_power;      // tau_t omega_w, power of the drive at the wheel [W]; negative
                                        // when the current is cut (the motors' friction, eq. 25)
  std::vector<double> battery_current;  // i_b [A] (eq. 32)
  std::vector<double> battery_voltage;  // V_mb, pack terminal voltage [V] (eq. 22a)
  std::vector<double> battery_ocv;      // V_bn, pack open-circuit voltage [V] (eq. 22b)
  std::vector<double> battery_power;    // P_b = V_bn i_b, drawn from the pack's energy [W] (eq. 33)
  std::vector<double> energy_used;      // e(0) - e [J]
  std::vector<double> efficiency_motor;       // omega_m tau_e / P_m [1]; NaN when P_m ~ 0
  std::vector<double> efficiency_electrical;  // P_m / P_b (controller and pack) [1]; NaN when P_b ~ 0
  std::vector<double> efficiency_powertrain;  // wheel_power / P_b [1]; NaN when P_b ~ 0
  // (the motor and power-train efficiencies are negative where i_m < i_m0: the shaft still drags)
  std::array<std::vector<double>, kNumConstraints> constraint;  // g_j <= 0 (constraints.h) [1]
  LapFigures figures;
};

// Evaluates the model at every node of `sol` (road length from `road`).
LapChannels ComputeLapChannels(const Vehicle& v, const RoadTrack& road, const LapSolution& sol);

}  // namespace ttz::lap
