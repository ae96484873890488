// The state and control vectors of the mono-wheel model (eq. 35), with the arc length s as the
// independent variable (eq. 37): s itself is not a state, the other eleven are.
//
// Sign convention of the model (the paper's): x forward, y right, z down. Compared with road.h5
// (x forward, y left, z up), n, alpha and kappa change sign; sigma, nu and tau do not
// (docs/lap.md, section "Frames").
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
  kNumStates
};

enum ControlIndex : int {
  kOmegaZ = 0,    // Omega_z, yaw rate [rad/s]
  kTauW,          // tau_w, wheel torque, traction positive [N m]
  kNumControls
};

inline constexpr std::array<const char*, kNumStates> kStateNames = {
    "n", "alpha", "V", "beta", "z", "phi", "omega_w", "T", "e", "omega_phi", "z_dot"};
inline constexpr std::array<const char*, kNumStates> kStateUnits = {
    "m", "rad", "m/s", "rad", "m", "rad", "rad/s", "degC", "J", "rad/s", "m/s"};
inline constexpr std::array<const char*, kNumControls> kControlNames = {"Omega_z", "tau_w"};
inline constexpr std::array<const char*, kNumControls> kControlUnits = {"rad/s", "N m"};

template <typename T>
using StateVector = std::array<T, kNumStates>;
template <typename T>
using ControlVector = std::array<T, kNumControls>;

}  // namespace ttz::lap
