// Tests of lap/lap_channels.h on a lap built by hand on a circle: every channel against a hand
// calculation from the power-train and tyre equations, and the headline figures.
#include "lap/lap_channels.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lap/testing/problem.h"

namespace ttz::lap {
namespace {

constexpr double kRadius = 50.0;  // [m]
constexpr int kNodes = 5;
constexpr double kSpacing = 10.0;  // [m]

using testing::Bx15;

// A level left-hand circle of radius kRadius (road.h5: kappa > 0 turning left).
RoadTrack LeftCircle() {
  RoadArtefact r;
  for (int i = 0; i <= 60; ++i) {
    r.s.push_back(i);
    r.kappa.push_back(1.0 / kRadius);
    for (auto* f : {&r.nu, &r.tau, &r.sigma, &r.banking}) f->push_back(0.0);
    r.width.push_back(8.0);
  }
  return RoadTrack(r);
}

// On the centre line, heading along it, speeding up from 15 m/s by 0.5 m/s per node, yawing with
// the road (Omega_z = V kappa), driving with 200 N m at the wheel except braking at the last node.
LapSolution HandMadeLap(const Vehicle& v) {
  LapSolution sol;
  const double kappa_model = -1.0 / kRadius;  // the model's frame: right turn positive
  for (int k = 0; k < kNodes; ++k) {
    const double V = 15.0 + 0.5 * k;
    StateVector<double> x{};
    x[kV] = V;
    x[kBeta] = 0.01;
    x[kZ] = v.M * v.g / v.K_s;
    x[kPhi] = -0.4;
    x[kOmegaW] = 1.01 * V / (v.r - x[kZ]);
    x[kT] = 40.0;
    x[kE] = v.e0 - 1e4 * k;
    x[kOmegaZ] = V * kappa_model;
    x[kTauW] = k + 1 < kNodes ? 200.0 : -300.0;
    sol.s.push_back(kSpacing * k);
    sol.x.push_back(x);
    sol.u.push_back({0.0, 0.0});
    sol.t.push_back(k == 0 ? 0.0 : sol.t.back() + kSpacing / (0.5 * (V + sol.x[k - 1][kV])));
  }
  sol.lambda.assign(kNodes, StateVector<double>{});
  return sol;
}

class LapChannelsTest : public ::testing::Test {
 protected:
  const Vehicle v = Bx15();
  const LapSolution sol = HandMadeLap(v);
  const LapChannels c = ComputeLapChannels(v, LeftCircle(), sol);
};

TEST_F(LapChannelsTest, EveryChannelHasOneValuePerNode) {
  for (const auto* f : {&c.sdot, &c.accel_long, &c.accel_lat, &c.tyre_load, &c.motor_power,
                        &c.battery_power, &c.efficiency_powertrain})
    EXPECT_EQ(f->size(), static_cast<size_t>(kNodes));
  for (const auto& g : c.constraint) EXPECT_EQ(g.size(), static_cast<size_t>(kNodes));
}

TEST_F(LapChannelsTest, KinematicsOnTheCentreLine) {
  for (int k = 0; k < kNodes; ++k) {
    const double V = sol.x[k][kV];
    // eq. 10a with n = 0, alpha = 0: sdot = V.
    EXPECT_NEAR(c.sdot[k], V, 1e-12);
    // Steady turning on a circle: V^2 / R, to the left (negative in the model's frame).
    EXPECT_NEAR(c.accel_lat[k], -V * V / kRadius, 1e-12);
    EXPECT_TRUE(std::isfinite(c.accel_long[k]));
  }
}

TEST_F(LapChannelsTest, TyreAndAero) {
  for (int k = 0; k < kNodes; ++k) {
    const double V = sol.x[k][kV];
    EXPECT_NEAR(c.aero_drag[k], 0.5 * 1.2 * 0.41 * V * V, 1e-9);                    // eq. 21
    EXPECT_NEAR(c.tyre_load[k], v.M * v.g, 0.1);                                    // K_s z, z_dot = 0
    const double fx = c.tyre_force_x[k] / (c.tyre_load[k] * v.mu_x);
    const double fy = c.tyre_force_y[k] / (c.tyre_load[k] * v.mu_y);
    EXPECT_NEAR(c.ellipse_usage[k], fx * fx + fy * fy, 1e-12);                       // eq. 19
    EXPECT_NEAR(c.constraint[kAdherence][k], c.ellipse_usage[k] - 1.0, 1e-12);
    EXPECT_NEAR(c.constraint[kBorderLeft][k], -1.0, 1e-12);  // n = 0: as far from both borders
  }
}

TEST_F(LapChannelsTest, PowerTrainAgainstHandCalculations) {
  const double dT = 40.0 - v.motor.T_0;
  const double k_V = v.motor.k_V0 - v.motor.sigma_m * dT, R_m = v.motor.R_m0 + v.motor.sigma_R * dT;
  for (int k = 0; k < kNodes; ++k) {
    const double e = sol.x[k][kE];
    const double omega_m = v.gamma_c * sol.x[k][kOmegaW];
    const double V_bn = v.pack.V_bn0 + (v.pack.V_bn1 - v.pack.V_bn0) * e / v.pack.e_i;  // eq. 22b
    const double i_b = c.battery_current[k], i_m = c.motor_current[k];
    EXPECT_NEAR(c.motor_speed[k], omega_m, 1e-12);
    EXPECT_NEAR(c.motor_voltage[k], k_V * omega_m + R_m * i_m, 1e-9);                 // eq. 24, 30
    EXPECT_NEAR(c.motor_power[k], c.motor_voltage[k] * i_m, 1e-9);
    EXPECT_NEAR(c.battery_ocv[k], V_bn, 1e-9);
    EXPECT_NEAR(c.battery_power[k], V_bn * i_b, 1e-9);                                // eq. 33
    EXPECT_NEAR(c.battery_voltage[k], V_bn - v.pack.R_b * i_b, 1e-9);                 // eq. 22a
    // The pack's internal loss: V_bn i_b - V_mb i_b = R_b i_b^2 (eq. 22).
    EXPECT_NEAR(c.battery_power[k] - c.battery_voltage[k] * i_b, v.pack.R_b * i_b * i_b, 1e-6);
    // eq. 23: the controller passes P_m = eta_mc V_mb i_b.
    EXPECT_NEAR(c.motor_power[k], v.eta_mc * c.battery_voltage[k] * i_b, 1e-6 * (1 + c.motor_power[k]));
  }
  // Driving with 200 N m at the wheel: tau_e = tau_t / (eta_c gamma_c) (eq. 31), tau_t ~ 200 N m.
  EXPECT_NEAR(c.motor_torque[0] * v.eta_c * v.gamma_c, 200.0, 0.01);
  EXPECT_NEAR(c.wheel_power[0], c.motor_torque[0] * v.eta_c * c.motor_speed[0], 1e-9);
}

TEST_F(LapChannelsTest, EfficienciesChainUpAndAreUndefinedWhenBraking) {
  for (int k = 0; k + 1 < kNodes; ++k) {
    EXPECT_GT(c.efficiency_motor[k], 0.5);
    EXPECT_LT(c.efficiency_motor[k], 1.0);
    EXPECT_GT(c.efficiency_electrical[k], 0.9);
    EXPECT_LT(c.efficiency_electrical[k], v.eta_mc);
    EXPECT_NEAR(c.efficiency_powertrain[k], c.efficiency_electrical[k] * c.efficiency_motor[k] * v.eta_c,
                1e-12);
  }
  EXPECT_TRUE(std::isnan(c.efficiency_motor[kNodes - 1]));
  EXPECT_TRUE(std::isnan(c.efficiency_powertrain[kNodes - 1]));
}

TEST_F(LapChannelsTest, EnergyAndHeadlineFigures) {
  for (int k = 0; k < kNodes; ++k) EXPECT_DOUBLE_EQ(c.energy_used[k], 1e4 * k);  // e0 - e
  EXPECT_DOUBLE_EQ(c.figures.energy_used, 4e4);
  EXPECT_DOUBLE_EQ(c.figures.energy_fraction, 4e4 / v.pack.e_i);
  EXPECT_DOUBLE_EQ(c.figures.top_speed, 17.0);
  EXPECT_DOUBLE_EQ(c.figures.start_speed, sol.x.front()[kV]);
  EXPECT_LT(c.figures.start_speed, c.figures.top_speed);
  EXPECT_DOUBLE_EQ(c.figures.lap_time, sol.t.back());
  EXPECT_DOUBLE_EQ(c.figures.average_speed, 40.0 / sol.t.back());
}

}  // namespace
}  // namespace ttz::lap
