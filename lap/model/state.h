// The state and control vectors of the mono-wheel model (eq. 35), with the arc length s as the
// independent variable (eq. 37): s itself is not a state, the other thirteen are.
//
// Decision (docs/lap.md, "Controls as states"): the paper's controls Omega_z and tau_w are states
// here and their time derivatives the controls, with a small cost on the squares of those rates
// (lap/model/cost.h).
// - Omega_z: as a control, the model has no yaw dynamics; the Hamiltonian is concave in Omega_z
//   in bends (H_uu < 0 from the Omega_z^2 terms of eq. 13b and 15), so the minimum-time optimum
//   chatters: the indirect solver's control elimination lost its minimum (H_uu -> 0 as the barrier
//   weight fell, measured) and a direct solver gained 0.5 % from node-to-node yaw oscillations.
//   As a state it also restores the dOmega_z/dt terms the paper drops in eq. 13a and 16.
// - tau_w: while braking, the current is cut and H is affine in tau_w (a singular arc): u* was
//   found only to ~1e-6, which left the transcription's residuals noisy at ~1e-6 (measured), and
//   a direct solver alternated the brake torque by hundreds of N m between intervals.
// With both as states, H is exactly quadratic in the controls and every path constraint is a
// state constraint.
//
// Sign convention of the model (the paper's): x forward, y right, z down. Compared with road.h5
// (x forward, y left, z up), n, alpha and kappa change sign; sigma, xi (banking), nu and tau do
// not (docs/lap.md, section "Frames").
#pragma once

#include <array>

namespace ttz::lap {

enum StateIndex : int {
  kN = 0,         // n, lateral offset of the contact point from the centre line, right positive [m]
  kAlpha,         // alpha, heading relative to the road, clockwise positive [rad]
  kV,             // V, speed [m/s]
  kBeta,          // beta, sideslip angle [rad]
  kZ,             // z, vertical displacement (tyre compression), down positive [m]
  kPhi,           // phi, roll angle, right positive [rad]
  kOmegaW,        // omega_w, wheel spin rate [rad/s]
  kT,             // T, motor temperature [degC]
  kE,             // e, battery energy [J]
  kOmegaPhi,      // omega_phi = dphi/dt [rad/s] (eq. 34)
  kZdot,          // z_dot = dz/dt [m/s] (eq. 34)
  kOmegaZ,        // Omega_z, yaw rate [rad/s] (a control in the paper's eq. 35)
  kTauW,          // tau_w, wheel torque, traction positive [N m] (a control in eq. 35)
  kNumStates
};

enum ControlIndex : int {
  kYawAccel = 0,  // dOmega_z/dt, yaw acceleration [rad/s^2]
  kTorqueRate,    // dtau_w/dt, rate of the wheel torque [N m/s]
  kNumControls
};

inline constexpr std::array<const char*, kNumStates> kStateNames = {
    "n", "alpha", "V", "beta", "z", "phi", "omega_w", "T", "e", "omega_phi", "z_dot", "Omega_z", "tau_w"};
inline constexpr std::array<const char*, kNumStates> kStateUnits = {
    "m", "rad", "m/s", "rad", "m", "rad", "rad/s", "degC", "J", "rad/s", "m/s", "rad/s", "N m"};
inline constexpr std::array<const char*, kNumControls> kControlNames = {"dOmega_z_dt", "dtau_w_dt"};
inline constexpr std::array<const char*, kNumControls> kControlUnits = {"rad/s^2", "N m/s"};

template <typename T>
using StateVector = std::array<T, kNumStates>;
template <typename T>
using ControlVector = std::array<T, kNumControls>;

}  // namespace ttz::lap
