// The running cost of the minimum-time problem per metre of arc length (eq. 37-38): the time
// dt/ds = 1 / sdot, plus the rider's effort c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2 + c_r omega_phi^2
// per unit time. The first two keep the yaw rate and the wheel torque, states of this model
// (lap/model/state.h), from chattering; the third, off in the reference bike (c_r = 0), prices the
// rider's rolling of the bike (docs/lap_log.md, "A price on rolling the bike"). The lap time reported
// is the time alone.
#pragma once

#include "lap/model/dynamics.h"

namespace ttz::lap {

// (c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2 + c_r omega_phi^2) / sdot [s/m].
template <typename T>
T EffortPerMetre(const Vehicle& v, const StateVector<T>& x, const ControlVector<T>& u,
                 const ModelPoint<T>& m) {
  return (v.yaw_accel_weight * u[kYawAccel] * u[kYawAccel] +
          v.torque_rate_weight * u[kTorqueRate] * u[kTorqueRate] +
          v.roll_rate_weight * x[kOmegaPhi] * x[kOmegaPhi]) /
         m.kin.sdot;
}

}  // namespace ttz::lap
