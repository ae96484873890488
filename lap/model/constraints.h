// The path constraints of eq. 39a-g, the motor-voltage limits of section 5 and the brake bound,
// each written as g(x) <= 0 scaled to order one (the states alone: no constraint involves the
// controls, which lap/solver/node.cc's one Newton step for them relies on), and the relaxed logarithmic barrier that
// turns them into a penalty of the Hamiltonian (lap/solver/indirect.h).
#pragma once

#include <array>
#include <cmath>

#include "lap/model/dynamics.h"

namespace ttz::lap {

enum ConstraintIndex : int {
  kBorderRight = 0,  // eq. 39a: n <= r_w/2 - margin
  kBorderLeft,       // eq. 39a: -n <= r_w/2 - margin
  kRollRateMax,      // eq. 39b
  kRollRateMin,
  kYawRateMax,       // eq. 39c
  kYawRateMin,
  kAdherence,        // eq. 39d (eq. 19)
  kMotorCurrent,     // eq. 39e
  kBatteryPower,     // eq. 39f
  kCharge,           // eq. 39g: e >= 0
  kMotorVoltageMax,  // section 5: V_mm <= V_max
  kMotorVoltagePack, // section 5: V_mm <= V_mb
  kBrakeTorque,      // tau_w >= -brake_torque_max (the control set U of eq. 38a)
  kNumConstraints
};

inline constexpr std::array<const char*, kNumConstraints> kConstraintNames = {
    "border_right", "border_left", "roll_rate_max", "roll_rate_min", "yaw_rate_max",
    "yaw_rate_min", "adherence", "motor_current", "battery_power", "charge",
    "motor_voltage_max", "motor_voltage_pack", "brake_torque"};

template <typename T>
using ConstraintVector = std::array<T, kNumConstraints>;

// g_j <= 0, each scaled by its limit. Every constraint is a function of the state alone (with the
// road's width): the tyre's ellipse and the power train's current, power and voltages follow from
// the state (tyre.h, powertrain.h), so the constraints can be checked at any point of a trajectory.
template <typename T>
ConstraintVector<T> ConstraintsFrom(const Vehicle& v, const StateVector<T>& x, const RoadPoint& road,
                                    const TyreForces<T>& tyre, const Powertrain<T>& power) {
  ConstraintVector<T> g;
  const double half = 0.5 * road.width - v.border_margin;
  g[kBorderRight] = x[kN] / half - 1.0;
  g[kBorderLeft] = -x[kN] / half - 1.0;
  g[kRollRateMax] = x[kOmegaPhi] / v.omega_phi_max - 1.0;
  g[kRollRateMin] = -x[kOmegaPhi] / v.omega_phi_max - 1.0;
  g[kYawRateMax] = x[kOmegaZ] / v.Omega_z_max - 1.0;
  g[kYawRateMin] = -x[kOmegaZ] / v.Omega_z_max - 1.0;
  g[kAdherence] = tyre.ellipse - 1.0;
  g[kMotorCurrent] = power.i_m / v.motor.current_max - 1.0;
  g[kBatteryPower] = power.P_b / v.P_b_max - 1.0;
  g[kCharge] = -x[kE] / v.pack.e_i;
  g[kMotorVoltageMax] = power.V_mm / v.motor.voltage_max - 1.0;
  g[kMotorVoltagePack] = (power.V_mm - power.V_mb) / v.motor.voltage_max;
  g[kBrakeTorque] = -x[kTauW] / v.brake_torque_max - 1.0;
  return g;
}

// Whether constraint j depends on state i: the states ConstraintsFrom reads itself and through
// the tyre and the power train as StateConstraints computes them (below). It is the sparsity of
// the constraints' Jacobians, which the Ipopt oracle passes on (lap/solver/ipopt_direct.cc);
// model_test checks it against automatic differentiation.
constexpr bool ConstraintUsesState(int j, int i) {
  switch (j) {
    case kBorderRight:
    case kBorderLeft:
      return i == kN;
    case kRollRateMax:
    case kRollRateMin:
      return i == kOmegaPhi;
    case kYawRateMax:
    case kYawRateMin:
      return i == kOmegaZ;
    case kAdherence:  // ComputeTyre's arguments
      return i == kV || i == kBeta || i == kZ || i == kPhi || i == kOmegaW || i == kZdot;
    case kCharge:
      return i == kE;
    case kBrakeTorque:
      return i == kTauW;
    default:  // current, power, voltages: ComputePowertrain's arguments
      return i == kTauW || i == kOmegaW || i == kV || i == kT || i == kE;
  }
}

// The number of states constraint j depends on.
constexpr int ConstraintStateCount(int j) {
  int n = 0;
  for (int i = 0; i < kNumStates; ++i) n += ConstraintUsesState(j, i) ? 1 : 0;
  return n;
}

// Whether g_j bounds one state: affine in that state (the one ConstraintUsesState names) and
// independent of the others. The Ipopt oracle makes these bounds of its unknowns at the nodes
// instead of rows of its constraint Jacobian (lap/solver/ipopt_direct.cc); model_test checks
// that each is affine.
constexpr bool IsStateBound(int j) {
  switch (j) {
    case kBorderRight:
    case kBorderLeft:
    case kRollRateMax:
    case kRollRateMin:
    case kYawRateMax:
    case kYawRateMin:
    case kCharge:
    case kBrakeTorque:
      return true;
    default:
      return false;
  }
}

// A state bound g_j <= 0 (IsStateBound(j)) as x[state] <= value (upper) or >= value (lower).
struct StateBound {
  int state;
  bool upper;
  double value;  // in the state's unit
};

// The constraints at a state alone (defined below).
template <typename T>
ConstraintVector<T> StateConstraints(const Vehicle& v, const StateVector<T>& x,
                                     const RoadPoint& road);

// The bound that g_j (IsStateBound(j)) sets at `road`, read off g_j itself: g_j = g0 + c x_i, so
// g_j <= 0 is x_i <= -g0 / c for c > 0 and x_i >= -g0 / c for c < 0.
inline StateBound StateBoundOf(const Vehicle& v, int j, const RoadPoint& road) {
  int i = 0;
  while (!ConstraintUsesState(j, i)) ++i;
  StateVector<double> x{};
  x[kV] = 10.0;  // a defined point of the tyre and power train, which g_j does not read
  const double g0 = StateConstraints(v, x, road)[j];
  x[i] = 1.0;
  const double c = StateConstraints(v, x, road)[j] - g0;
  return {i, c > 0.0, -g0 / c};
}

// The constraints at a point of the model already evaluated (m = EvaluateModel(v, x, u, road)).
template <typename T>
ConstraintVector<T> EvaluateConstraints(const Vehicle& v, const StateVector<T>& x,
                                        const ControlVector<T>&, const RoadPoint& road,
                                        const ModelPoint<T>& m) {
  return ConstraintsFrom(v, x, road, m.tyre, m.power);
}

// The constraints at a state alone (the tyre and power train evaluated here).
template <typename T>
ConstraintVector<T> StateConstraints(const Vehicle& v, const StateVector<T>& x,
                                     const RoadPoint& road) {
  return ConstraintsFrom(v, x, road,
                         ComputeTyre(v, x[kV], x[kBeta], x[kZ], x[kPhi], x[kOmegaW], x[kZdot]),
                         ComputePowertrain(v, x[kTauW], x[kOmegaW], x[kV], x[kT], x[kE]));
}

// The relaxed barrier ("activation") of one constraint g <= 0: -log(-g) for g <= -delta, and for
// g > -delta the quadratic that matches its value, slope and curvature at -delta, so the penalty is
// C2 and finite everywhere and a slightly violated constraint costs a steep but finite amount.
template <typename T>
T RelaxedBarrier(const T& g, double delta) {
  using std::log;
  if (g <= -delta) return -log(-g);
  const T d = (g + delta) / delta;
  return -std::log(delta) + d + 0.5 * d * d;
}

}  // namespace ttz::lap
