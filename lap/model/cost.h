// The running cost of the minimum-time problem per metre of arc length (eq. 37-38): the time
// dt/ds = 1 / sdot, plus the rider's effort c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2 per unit time,
// which keeps the yaw rate and the wheel torque, states of this model (lap/model/state.h), from
// chattering. The lap time reported is the time alone.
#pragma once

#include "lap/model/dynamics.h"

namespace ttz::lap {

// (c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2) / sdot [s/m].
template <typename T>
T EffortPerMetre(const Vehicle& v, const ControlVector<T>& u, const ModelPoint<T>& m) {
  return (v.yaw_accel_weight * u[kYawAccel] * u[kYawAccel] +
          v.torque_rate_weight * u[kTorqueRate] * u[kTorqueRate]) /
         m.kin.sdot;
}

}  // namespace ttz::lap
