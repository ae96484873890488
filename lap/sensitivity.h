// Design sensitivities of a solved lap: how much lap time each bike.yaml value buys, from the one
// solve, by the adjoint (envelope) theorem applied to the transcription the indirect solver solves
// (lap/solver/transcription.h).
//
// The solver minimises J = sum_k h_k L_k + sum_k B_k (the lap time with the barriers' and the
// rider's effort terms at the answer's eps: lap/solver/hamiltonian.h, node_barrier.h) subject to
// the midpoint defects x~_{k+1} - x~_k = h_k F_k and the fixed start state x~_0. At its optimum
// the Lagrangian's derivative in a bike value p is the optimum's:
//
//   dJ/dp = sum_k h_k dH/dp(x~_{k+1/2}, mu~_k, u~_k) + sum_k dB_k/dp(x~_k) + lambda~_0 . dx~_0/dp
//
// with H at interval k's midpoint with the multiplier of its defect (Transcription::MidCostate),
// B_k the barrier of node k, and lambda~_0 = dJ/dx~_0 (the costates' discrete adjoint equations
// make it the node-0 costate). States, costates and controls are held: they are optimal, so their
// own change does not move J to first order. The scales stay the base bike's (the model is
// evaluated in physical units: they only change variables). dH/dp and dB/dp are central
// differences of the value (a step of 1e-6 of it), the model rebuilt by MakeVehicle each time,
// so that derived figures follow (the total mass from a motor's or the pack's, the pack's
// voltage, resistance and energy from a cell's).
//
// The start state x_0 follows the value as the solvers' start does, as the quasi-steady state
// at the bike's initial speed, motor temperature and charge (lap/qss.h); its change is taken from
// the centre line's quasi-steady lap on the mesh's first kStartNodes nodes (the start's
// acceleration is the first interval's; the racing line's offset, which `lap` starts on, does
// not depend on the bike). The mesh is held.
//
// What it is: the slope of J, which is the lap time's but for the barriers' and the effort's
// share of it (~1e-4 at eps 1e-4). Not for the effort weights themselves (bike.yaml's
// limits.*_weight_*), whose dJ/dp is the effort's integral, not a lap time: they are left out.
// Checked against laps solved again with the value changed (lap/sensitivity_test.cc). Needs the
// indirect solver's costates and barrier weight: an Ipopt lap (eps 0, constraints as multipliers,
// not barriers) has none.
#pragma once

#include <string>
#include <vector>

#include "lap/bike.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct DesignSensitivity {
  std::string key;    // bike.yaml path, e.g. "chassis.base_mass_kg" (its unit is in its name)
  std::string kind;   // SensitivityKind(key)
  double value;       // the value in the lap's bike [unit of the key]
  double per_unit;    // dJ/dp [s per unit of the key]
  // The lap time 1 % more of the value costs [s]: per_unit * value / 100, the value taken in
  // kelvin for the temperatures in degC (keys ending "_c"), so that 1 % does not depend on where
  // the scale's zero is. 0 for a value of 0; for a negative value (a downforce, C_l < 0) 1 % more
  // is 1 % further from zero.
  double per_percent;
};

// The bike.yaml values DesignSensitivities covers: RealBikeKeys but the rider's effort weights.
std::vector<std::string> SensitivityKeys();

// What kind of change a bike.yaml value's sensitivity is, so that a report of what buys lap time
// can keep to what a team can change:
//   "design"     the bike and its set-up (chassis, tyre, aero but the air's density, motor,
//                controller, battery, drive, the brake's torque);
//   "rider"      the rider's limits (roll and yaw rate, the margin to the borders);
//   "condition"  the day and the start: the air's density, gravity, the ambient temperature and
//                the initial speed, motor temperature and charge;
//   "reference"  a model's reference point, not a change of anything: the temperature at which
//                the motor's R_m0, k_V0 and k_tau0 are given (1 % more of it with them held is a
//                cooler motor's constants at the same temperatures).
const char* SensitivityKind(const std::string& key);

// Whether `sol` carries what DesignSensitivities needs: costates at every node, the intervals'
// controls and a barrier weight eps > 0 (the indirect solver's laps).
bool HasSensitivities(const LapSolution& sol);

// dJ/dp for every value of SensitivityKeys (file order) of the lap `sol` of `bike` on `road`;
// `threads` evaluate the values in parallel. Empty, with the reason in *why_not, when
// !HasSensitivities(sol) or when the transcription rebuilt from `sol` is not its solution (max
// |residual| over 1e-6, i.e. `sol` is not a converged lap of this bike and road with node
// barriers and a free end).
std::vector<DesignSensitivity> DesignSensitivities(const BikeParams& bike, const RoadTrack& road,
                                                   const LapSolution& sol, int threads, std::string* why_not);

}  // namespace ttz::lap
