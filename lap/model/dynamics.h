// The state equations of the mono-wheel in the arc-length domain (eq. 36-38):
// x' = dx/ds = (A_s^-1 f(x, u)) / sdot, together with every channel lap.h5 reports.
#pragma once

#include "lap/model/chassis.h"
#include "lap/model/kinematics.h"
#include "lap/model/powertrain.h"
#include "lap/model/tyre.h"

namespace ttz::lap {

template <typename T>
struct ModelPoint {
  StateVector<T> dx_ds;  // x' [state unit per m]
  Kinematics<T> kin;
  TyreForces<T> tyre;
  Powertrain<T> power;
  T D, L;                // aerodynamic drag and lift [N]
  std::array<T, kNumAccels> acc;  // dV/dt, dbeta/dt, d2z/dt2, d2phi/dt2, domega_w/dt
};

template <typename T>
ModelPoint<T> EvaluateModel(const Vehicle& v, const StateVector<T>& x, const ControlVector<T>& u,
                            const RoadPoint& road) {
  ModelPoint<T> m;
  m.kin = ComputeKinematics(x, u, road);
  m.tyre = ComputeTyre(v, x[kV], x[kBeta], x[kZ], x[kPhi], x[kOmegaW], x[kZdot]);
  ComputeAero(v, x[kV], &m.D, &m.L);
  m.power = ComputePowertrain(v, x[kTauW], x[kOmegaW], x[kV], x[kT], x[kE]);
  const ChassisLoads<T> loads{m.tyre.F_x, m.tyre.F_y, m.tyre.N, m.D, m.L, x[kTauW], m.tyre.tau_r};
  m.acc = SolveAccelerations(NewtonEuler(v, x, m.kin, loads, road));
  const T inv_sdot = 1.0 / m.kin.sdot;  // eq. 37: x' = x_dot / sdot
  StateVector<T>& f = m.dx_ds;
  f[kN] = m.kin.ndot * inv_sdot;
  f[kAlpha] = m.kin.alphadot * inv_sdot;
  f[kV] = m.acc[kVdot] * inv_sdot;
  f[kBeta] = m.acc[kBetadot] * inv_sdot;
  f[kZ] = x[kZdot] * inv_sdot;                 // eq. 34
  f[kPhi] = x[kOmegaPhi] * inv_sdot;           // eq. 34
  f[kOmegaW] = m.acc[kOmegaWdot] * inv_sdot;
  f[kT] = m.power.T_dot * inv_sdot;
  f[kE] = m.power.e_dot * inv_sdot;
  f[kOmegaPhi] = m.acc[kPhiddot] * inv_sdot;
  f[kZdot] = m.acc[kZddot] * inv_sdot;
  f[kOmegaZ] = u[kYawAccel] * inv_sdot;
  f[kTauW] = u[kTorqueRate] * inv_sdot;
  return m;
}

}  // namespace ttz::lap
