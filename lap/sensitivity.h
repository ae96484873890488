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
// own change does not move J to first order. dH/dp and dB/dp are central differences of the value
// (a step of 1e-6 of it), the model rebuilt by MakeVehicle each time, so that derived figures
// follow (the total mass from a motor's or the pack's, the pack's voltage, resistance and energy
// from a cell's). Of the start state, bike.yaml sets the speed, motor temperature and charge; the
// other start states (the quasi-steady state at the start, lap/qss.h) and the mesh are held.
//
// What it is: the slope of the lap's cost at the answer's eps (1e-4: the barriers' share of J is
// ~1e-4 of it), i.e. the lap time a small change of one value buys, for a lap solved again on the
// same mesh. Checked against laps solved again with the value changed (lap/sensitivity_test.cc).
// Needs the indirect solver's costates and barrier weight: an Ipopt lap (eps 0, constraints as
// multipliers, not barriers) has none.
#pragma once

#include <string>
#include <vector>

#include "lap/bike.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct DesignSensitivity {
  std::string key;    // bike.yaml path, e.g. "chassis.base_mass_kg" (its unit is in its name)
  double value;       // the value in the lap's bike [unit of the key]
  double per_unit;    // dJ/dp [s per unit of the key]
  double per_percent; // per_unit * value / 100: the lap time 1 % more of the value costs [s]
};

// Whether `sol` carries what DesignSensitivities needs: costates at every node and a barrier
// weight eps > 0 (the indirect solver's laps).
bool HasSensitivities(const LapSolution& sol);

// dJ/dp for every real bike.yaml value (RealBikeKeys, file order) of the lap `sol` of `bike` on
// `road`; empty when !HasSensitivities(sol). `threads` evaluate the values in parallel.
std::vector<DesignSensitivity> DesignSensitivities(const BikeParams& bike, const RoadTrack& road,
                                                   const LapSolution& sol, int threads);

}  // namespace ttz::lap
