#include "lap/model/vehicle.h"

namespace ttz::lap {

Vehicle MakeVehicle(const BikeParams& p) {
  Vehicle v;
  v.M = TotalMass(p);
  v.h = p.chassis.h;
  v.I_xx = p.chassis.I_xx;
  v.I_yy = p.chassis.I_yy;
  v.I_zz = p.chassis.I_zz;
  v.I_gy = p.chassis.I_gy;
  v.I_wy = p.chassis.I_wy;
  v.r = p.tyre.r;
  v.r_t = p.tyre.r_t;
  v.K_kappa = p.tyre.K_kappa;
  v.K_beta = p.tyre.K_beta;
  v.K_phi = p.tyre.K_phi;
  v.K_s = p.tyre.K_s;
  v.K_c = p.tyre.K_c;
  v.mu_x = p.tyre.mu_x;
  v.mu_y = p.tyre.mu_y;
  v.mu_r = p.tyre.mu_r;
  v.drag_k = 0.5 * p.aero.rho * p.aero.C_d;  // eq. 21
  v.lift_k = 0.5 * p.aero.rho * p.aero.C_l;
  v.motor = MotorsInParallel(p);
  v.eta_mc = p.controller.eta_mc;
  v.pack = Pack(p);
  v.P_b_max = p.battery.power_max;
  v.gamma_c = p.drive.gamma_c;
  v.eta_c = p.drive.eta_c;
  v.g = p.environment.g;
  v.T_ext = p.environment.T_ext;
  v.omega_phi_max = p.limits.omega_phi_max;
  v.Omega_z_max = p.limits.Omega_z_max;
  v.border_margin = p.limits.border_margin;
  v.brake_torque_max = p.limits.brake_torque_max;
  v.yaw_accel_weight = p.limits.yaw_accel_weight;
  v.torque_rate_weight = p.limits.torque_rate_weight;
  v.roll_rate_weight = p.limits.roll_rate_weight;
  v.V0 = p.initial.V;
  v.T0 = p.initial.T;
  v.e0 = InitialEnergy(p);
  return v;
}

}  // namespace ttz::lap
