#include "lap/qss.h"

#include <algorithm>
#include <cmath>

#include "lap/model/powertrain.h"

namespace ttz::lap {
namespace {

double RollingRadius(const Vehicle& v) { return v.r - v.M * v.g / v.K_s; }

// Largest wheel torque tau_t [N m] within every power-train limit, by bisection on the torque
// (each limit grows monotonically with torque).
double MaxWheelTorque(const Vehicle& v, double omega_w, double e, double T) {
  auto ok = [&](double tau) {
    const Powertrain<double> p = ComputePowertrain(v, tau, omega_w, 0.0, T, e);
    return p.i_m <= v.motor.current_max && p.P_b <= v.P_b_max &&
           p.V_mm <= v.motor.voltage_max && p.V_mm <= p.V_mb;
  };
  double lo = 0.0, hi = 5000.0;
  if (!ok(lo)) return 0.0;
  for (int i = 0; i < 60; ++i) (ok(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

// Longitudinal acceleration budget left by the lateral use of the ellipse [m/s^2].
double EllipseLongitudinal(const Vehicle& v, double V, double kappa) {
  const double lateral = V * V * std::abs(kappa) / (v.mu_y * v.g);
  return v.mu_x * v.g * std::sqrt(std::max(0.0, 1.0 - lateral * lateral));
}

}  // namespace

double MaxTractionForce(const Vehicle& v, double V, double e, double T) {
  const double R = RollingRadius(v);
  return MaxWheelTorque(v, V / R, e, T) / R;
}

QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh) {
  const int n = static_cast<int>(mesh.size());
  const double safety = 0.95;  // of the adherence, so the guess is strictly inside the ellipse
  std::vector<RoadPoint> rp(n);
  std::vector<double> vmax(n);
  for (int i = 0; i < n; ++i) {
    rp[i] = road.At(mesh[i]);
    const double k = std::max(std::abs(rp[i].kappa), 1e-9);
    vmax[i] = std::min(150.0, std::sqrt(safety * v.mu_y * v.g / k));
  }
  // The wheel's spin inertia adds to the mass being accelerated or braked (eq. 16).
  const double R = RollingRadius(v), M_eff = v.M + v.I_wy / (R * R);
  QssLap q;
  q.s = mesh;
  q.V.assign(n, 0.0);
  q.V[0] = std::min(v.V0, vmax[0]);
  // Forward: traction under the power train and the ellipse.
  for (int i = 0; i + 1 < n; ++i) {
    const double V = q.V[i], h = mesh[i + 1] - mesh[i];
    const double resist = v.drag_k * V * V / v.M + v.mu_r * v.g + v.g * std::sin(rp[i].sigma);
    const double ax = std::min(MaxTractionForce(v, V, v.e0, v.T0) / M_eff,
                               safety * EllipseLongitudinal(v, V, rp[i].kappa) * v.M / M_eff) -
                      resist * v.M / M_eff;
    q.V[i + 1] = std::min(vmax[i + 1], std::sqrt(std::max(1.0, V * V + 2.0 * ax * h)));
  }
  // Backward: braking under the ellipse.
  for (int i = n - 1; i > 0; --i) {
    const double V = q.V[i], h = mesh[i] - mesh[i - 1];
    const double resist = v.drag_k * V * V / v.M + v.mu_r * v.g + v.g * std::sin(rp[i].sigma);
    const double ab = (safety * EllipseLongitudinal(v, V, rp[i].kappa) + resist) * v.M / M_eff;
    q.V[i - 1] = std::min(q.V[i - 1], std::sqrt(V * V + 2.0 * std::max(ab, 0.1) * h));
  }
  // Time and the model states that go with the profile.
  q.t.assign(n, 0.0);
  for (int i = 0; i + 1 < n; ++i)
    q.t[i + 1] = q.t[i] + 2.0 * (mesh[i + 1] - mesh[i]) / (q.V[i] + q.V[i + 1]);
  q.lap_time = q.t.back();
  q.x.resize(n);
  q.u.resize(n);
  double e = v.e0;
  const double N = v.M * v.g;
  for (int i = 0; i < n; ++i) {
    const double V = q.V[i];
    const double ax = i + 1 < n ? (q.V[i + 1] * q.V[i + 1] - V * V) / (2 * (mesh[i + 1] - mesh[i]))
                                : 0.0;
    const double Oz = V * rp[i].kappa;
    const double phi = std::atan(V * Oz / v.g);
    StateVector<double>& x = q.x[i];
    x[kN] = 0.0;
    x[kAlpha] = 0.0;
    x[kV] = V;
    x[kPhi] = phi;
    x[kBeta] = (V * Oz / v.g - v.K_phi * phi) / v.K_beta;
    x[kZ] = (N - v.lift_k * V * V) / v.K_s;
    const double resist = v.drag_k * V * V / v.M + v.g * std::sin(rp[i].sigma);
    const double Fx = v.M * (ax + resist);
    const double kappa_w = Fx / (N * v.K_kappa);
    const double R_e = v.r - v.r_t + std::cos(phi) * (v.r_t - x[kZ]);
    x[kOmegaW] = V * (1.0 + kappa_w) / R_e;
    x[kT] = v.T0;
    x[kE] = e;
    x[kOmegaPhi] = 0.0;
    x[kZdot] = 0.0;
    const double tau_w = Fx * R_e + v.mu_r * N * R_e;
    q.u[i] = {Oz, tau_w};
    const Powertrain<double> p = ComputePowertrain(v, tau_w, x[kOmegaW], V, v.T0, e);
    if (i + 1 < n) e += p.e_dot * (q.t[i + 1] - q.t[i]);
  }
  return q;
}

}  // namespace ttz::lap
