#include "lap/lap_channels.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lap/model/dynamics.h"

namespace ttz::lap {
namespace {

// An efficiency out / in, or NaN where the input power is too small for the ratio to mean
// anything (coasting and braking: the smoothed motor current of eq. 25 leaves a few watts).
double Efficiency(double out, double in, double min_power) {
  return in > min_power ? out / in : std::numeric_limits<double>::quiet_NaN();
}

void Resize(LapChannels* c, size_t n) {
  for (auto* f : {&c->sdot, &c->accel_long, &c->accel_lat, &c->tyre_load, &c->tyre_force_x,
                  &c->tyre_force_y, &c->ellipse_usage, &c->tyre_slip, &c->aero_drag,
                  &c->motor_torque, &c->motor_speed, &c->motor_current, &c->motor_voltage,
                  &c->motor_power, &c->wheel_power, &c->battery_current, &c->battery_voltage,
                  &c->battery_ocv, &c->battery_power, &c->energy_used, &c->efficiency_motor,
                  &c->efficiency_electrical, &c->efficiency_powertrain})
    f->resize(n);
  for (auto& g : c->constraint) g.resize(n);
}

// The channels of node k from one evaluation of the model.
void FillNode(const Vehicle& v, const StateVector<double>& x, const ControlVector<double>& u,
              const RoadPoint& rp, double e0, size_t k, LapChannels* c) {
  const ModelPoint<double> m = EvaluateModel(v, x, u, rp);
  const Powertrain<double>& p = m.power;
  c->sdot[k] = m.kin.sdot;
  c->accel_long[k] = m.acc[kVdot];
  // Lateral acceleration: V Omega_z, the centripetal acceleration of the yawing frame (eq. 11),
  // exact in steady cornering (V^2 / R on a level circle of radius R; on a banked one its part in
  // the road's plane, V^2 cos(xi) / R). The kinematic one adds
  // d(v_y)/dt = -d(V beta)/dt, which follows the fast sideslip dynamics and is small.
  c->accel_lat[k] = x[kV] * x[kOmegaZ];
  c->tyre_load[k] = m.tyre.N;
  c->tyre_force_x[k] = m.tyre.F_x;
  c->tyre_force_y[k] = m.tyre.F_y;
  c->ellipse_usage[k] = m.tyre.ellipse;
  c->tyre_slip[k] = m.tyre.kappa_w;
  c->aero_drag[k] = m.D;
  c->motor_torque[k] = p.tau_e;
  c->motor_speed[k] = p.omega_m;
  c->motor_current[k] = p.i_m;
  c->motor_voltage[k] = p.V_mm;
  c->motor_power[k] = p.P_m;
  c->wheel_power[k] = p.tau_t * x[kOmegaW];  // = eta_c omega_m tau_e (eq. 31)
  c->battery_current[k] = p.i_b;
  c->battery_voltage[k] = p.V_mb;
  c->battery_ocv[k] = p.V_bn;
  c->battery_power[k] = p.P_b;
  c->energy_used[k] = e0 - x[kE];
  const double min_power = 1e-3 * v.P_b_max;  // 142 W for the BX-15
  c->efficiency_motor[k] = Efficiency(p.omega_m * p.tau_e, p.P_m, min_power);  // eq. 28
  c->efficiency_electrical[k] = Efficiency(p.P_m, p.P_b, min_power);           // eq. 22-23
  c->efficiency_powertrain[k] = Efficiency(c->wheel_power[k], p.P_b, min_power);
  const ConstraintVector<double> g = EvaluateConstraints(v, x, u, rp, m);
  for (int j = 0; j < kNumConstraints; ++j) c->constraint[j][k] = g[j];
}

LapFigures Figures(const Vehicle& v, const LapSolution& sol, const LapChannels& c) {
  LapFigures f;
  f.lap_time = sol.t.back();
  f.energy_used = c.energy_used.back();
  f.energy_fraction = f.energy_used / v.pack.e_i;
  for (const StateVector<double>& x : sol.x) f.top_speed = std::max(f.top_speed, x[kV]);
  f.start_speed = sol.x.front()[kV];
  f.average_speed = (sol.s.back() - sol.s.front()) / f.lap_time;
  return f;
}

}  // namespace

LapChannels ComputeLapChannels(const Vehicle& v, const RoadTrack& road, const LapSolution& sol) {
  LapChannels c;
  const size_t n = sol.s.size();
  Resize(&c, n);
  const double e0 = sol.x.front()[kE];
  for (size_t k = 0; k < n; ++k) FillNode(v, sol.x[k], sol.u[k], road.At(sol.s[k]), e0, k, &c);
  c.figures = Figures(v, sol, c);
  return c;
}

}  // namespace ttz::lap
