// The Hamiltonian of the minimum-time problem in the arc-length domain (eq. 38) with the path
// constraints as relaxed barrier penalties and the rider's effort, in scaled states x~ = x / S and controls u~ = u / S_u:
//
//   H(x~, lambda~, u~) = (1 + eps sum_j P_delta(g_j(x))) / sdot
//                        + (c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2 + c_r omega_phi^2) / sdot
//                        + sum_i lambda~_i x_i' / S_i
//
// (x' from lap/model/dynamics.h, g_j and P_delta from lap/model/constraints.h, the steering
// effort from lap/model/cost.h). The necessary
// conditions are x~' = H_lambda~, lambda~' = -H_x~ and H_u~ = 0 (lap/solver/node.h).
#pragma once

#include <array>

#include "lap/model/constraints.h"
#include "lap/model/cost.h"
#include "lap/model/dynamics.h"

namespace ttz::lap {

// Scales of the states and controls: x = S x~, u = S_u u~ (unit of the quantity).
struct Scales {
  StateVector<double> state;
  ControlVector<double> control;
};
Scales DefaultScales(const Vehicle& v);

struct BarrierWeight {
  double eps;    // barrier weight [1]
  double delta;  // relaxation of the log barrier, min(1e-3, 0.1 eps) (lap-solver notes)
};

template <typename T>
struct HamiltonianValue {
  T H;
  StateVector<T> f;  // x~' = x' / S
  T dt_ds;           // 1 / sdot [s/m]
};

template <typename T>
HamiltonianValue<T> EvaluateHamiltonian(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                                        const BarrierWeight& w, const StateVector<T>& xs,
                                        const ControlVector<T>& us,
                                        const StateVector<double>& lambda) {
  StateVector<T> x;
  ControlVector<T> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = xs[i] * sc.state[i];
  for (int i = 0; i < kNumControls; ++i) u[i] = us[i] * sc.control[i];
  const ModelPoint<T> m = EvaluateModel(v, x, u, road);
  const ConstraintVector<T> g = EvaluateConstraints(v, x, u, road, m);
  T penalty = Cst<T>(0.0);
  for (int j = 0; j < kNumConstraints; ++j) penalty = penalty + RelaxedBarrier(g[j], w.delta);
  HamiltonianValue<T> out;
  out.dt_ds = 1.0 / m.kin.sdot;
  out.H = (1.0 + w.eps * penalty) * out.dt_ds + EffortPerMetre(v, x, u, m);
  for (int i = 0; i < kNumStates; ++i) {
    out.f[i] = m.dx_ds[i] / sc.state[i];
    out.H = out.H + lambda[i] * out.f[i];
  }
  return out;
}

}  // namespace ttz::lap
