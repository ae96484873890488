// Tests of the mono-wheel model: derivatives against numerical differentiation (every function
// the solver differentiates), the power train against hand calculations, and physical limits.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "lap/model/constraints.h"
#include "lap/model/cost.h"
#include "lap/model/dynamics.h"
#include "lap/model/vehicle.h"
#include "lap/testing/problem.h"

namespace ttz::lap {
namespace {

using testing::Bx15;

RoadPoint Curvy() {
  RoadPoint r;
  r.kappa = 0.01;
  r.nu = 0.002;
  r.tau = -0.001;
  r.dkappa = 1e-4;
  r.dnu = -2e-5;
  r.dtau = 3e-5;
  r.sigma = 0.05;
  r.xi = 0.04;
  r.width = 7.0;
  return r;
}

// A state at speed V leaning phi with a little of every other state.
StateVector<double> SomeState(const Vehicle& v, double V) {
  StateVector<double> x;
  x[kN] = 0.7;
  x[kAlpha] = 0.03;
  x[kV] = V;
  x[kBeta] = 0.01;
  x[kZ] = v.M * v.g / v.K_s;
  x[kPhi] = 0.3;
  x[kOmegaW] = V / (v.r - 0.01) * 1.02;
  x[kT] = 45.0;
  x[kE] = 0.6 * v.pack.e_i;
  x[kOmegaPhi] = 0.1;
  x[kZdot] = 0.01;
  x[kOmegaZ] = 0.12;
  x[kTauW] = 300.0;
  return x;
}

// dx/ds, the constraints and the effort as a cost function of (x, u), for GradientChecker.
struct ModelFunctor {
  const Vehicle* v;
  RoadPoint road;
  template <typename T>
  bool operator()(const T* x_in, const T* u_in, T* out) const {
    StateVector<T> x;
    ControlVector<T> u;
    for (int i = 0; i < kNumStates; ++i) x[i] = x_in[i];
    for (int i = 0; i < kNumControls; ++i) u[i] = u_in[i];
    const ModelPoint<T> m = EvaluateModel(*v, x, u, road);
    const ConstraintVector<T> g = EvaluateConstraints(*v, x, u, road, m);
    for (int i = 0; i < kNumStates; ++i) out[i] = m.dx_ds[i];
    for (int j = 0; j < kNumConstraints; ++j) out[kNumStates + j] = g[j];
    out[kNumStates + kNumConstraints] = EffortPerMetre(*v, x, u, m);
    return true;
  }
};

TEST(ModelTest, DerivativesMatchNumericalDifferentiation) {
  // First derivatives of x', of every constraint and of the effort (with a price on the roll
  // rate) with respect to every state and control, automatic (Jets) against central differences.
  Vehicle v = Bx15();
  v.roll_rate_weight = 0.03;
  const ModelFunctor f{&v, Curvy()};
  constexpr int kOut = kNumStates + kNumConstraints + 1, kIn = kNumStates + kNumControls;
  std::array<double, kIn> p;
  const StateVector<double> x = SomeState(v, 30.0);
  std::copy(x.begin(), x.end(), p.begin());
  p[kNumStates + kYawAccel] = 0.4;
  p[kNumStates + kTorqueRate] = 500.0;
  using J = ceres::Jet<double, kIn>;
  std::array<J, kIn> pj;
  for (int i = 0; i < kIn; ++i) pj[i] = J(p[i], i);
  std::array<J, kOut> out;
  f(pj.data(), pj.data() + kNumStates, out.data());
  for (int j = 0; j < kIn; ++j) {
    const double h = 1e-6 * std::max(1e-2, std::abs(p[j]));
    auto pp = p, pm = p;
    pp[j] += h;
    pm[j] -= h;
    std::array<double, kOut> op, om;
    f(pp.data(), pp.data() + kNumStates, op.data());
    f(pm.data(), pm.data() + kNumStates, om.data());
    for (int i = 0; i < kOut; ++i) {
      const double numeric = (op[i] - om[i]) / (2 * h);
      EXPECT_NEAR(out[i].v[j], numeric, 1e-5 * std::abs(numeric) + 1e-9)
          << "output " << i << " input " << j;
    }
  }
}

TEST(ModelTest, SecondDerivativesOfNestedJetsMatchDifferencesOfFirst) {
  // The solver takes the costate equations' Jacobian from nested Jets; check them against central
  // differences of first-order Jets on the speed derivative V' (which depends on everything).
  using J1 = ceres::Jet<double, kNumStates>;
  using J2 = ceres::Jet<J1, kNumStates>;
  const Vehicle v = Bx15();
  const StateVector<double> x0 = SomeState(v, 25.0);
  const ControlVector<double> u0 = {0.1, 200.0};
  auto first = [&](const StateVector<double>& x) {
    StateVector<J1> xj;
    ControlVector<J1> uj = {J1(u0[0]), J1(u0[1])};
    for (int i = 0; i < kNumStates; ++i) xj[i] = J1(x[i], i);
    return EvaluateModel(v, xj, uj, Curvy()).dx_ds[kV];
  };
  StateVector<J2> x2;
  ControlVector<J2> u2 = {J2(J1(u0[0])), J2(J1(u0[1]))};
  for (int i = 0; i < kNumStates; ++i) x2[i] = J2(J1(x0[i], i), i);
  const J2 f2 = EvaluateModel(v, x2, u2, Curvy()).dx_ds[kV];
  for (int j = 0; j < kNumStates; ++j) {
    StateVector<double> xp = x0, xm = x0;
    const double h = 1e-5 * std::max(1.0, std::abs(x0[j]));
    xp[j] += h;
    xm[j] -= h;
    const J1 fp = first(xp), fm = first(xm);
    for (int i = 0; i < kNumStates; ++i) {
      const double numeric = (fp.v[i] - fm.v[i]) / (2 * h);
      const double scale = std::max(1e-6, std::abs(numeric));
      EXPECT_NEAR(f2.v[j].v[i], numeric, 1e-4 * scale + 1e-9) << "d2 V' / dx" << i << " dx" << j;
    }
    EXPECT_NEAR(f2.a.v[j], f2.v[j].a, 1e-12 * std::max(1.0, std::abs(f2.a.v[j])));
  }
}

// ConstraintUsesState is the structure of the constraints' Jacobian that the Ipopt oracle gives
// Ipopt: every derivative outside it must be exactly zero, at the model's evaluation (with the
// controls) as at the state alone, braking and driving, and not all inside it may vanish.
TEST(ModelTest, ConstraintsDependOnTheDeclaredStatesOnly) {
  using J = ceres::Jet<double, kNumStates + kNumControls>;
  const Vehicle v = Bx15();
  for (double tau_w : {300.0, -400.0}) {
    StateVector<double> x0 = SomeState(v, 40.0);
    x0[kTauW] = tau_w;
    StateVector<J> x;
    ControlVector<J> u;
    for (int i = 0; i < kNumStates; ++i) x[i] = J(x0[i], i);
    for (int i = 0; i < kNumControls; ++i) u[i] = J(0.5 + i, kNumStates + i);
    const ConstraintVector<J> g = EvaluateConstraints(v, x, u, Curvy(), EvaluateModel(v, x, u, Curvy()));
    const ConstraintVector<J> gs = StateConstraints(v, x, Curvy());
    for (int j = 0; j < kNumConstraints; ++j) {
      int used = 0;
      for (int i = 0; i < kNumStates + kNumControls; ++i) {
        const bool declared = i < kNumStates && ConstraintUsesState(j, i);
        if (!declared) {
          EXPECT_EQ(g[j].v[i], 0.0) << kConstraintNames[j] << " on variable " << i;
          EXPECT_EQ(gs[j].v[i], 0.0) << kConstraintNames[j] << " on variable " << i;
        }
        used += declared && g[j].v[i] != 0.0 ? 1 : 0;
      }
      EXPECT_GT(used, 0) << kConstraintNames[j];
    }
  }
}

// The state bounds (IsStateBound) are affine in their one state, and StateBoundOf reads the
// bound where g_j = 0, on the side where g_j < 0: what the Ipopt oracle relies on to make them
// bounds of its unknowns. The other constraints are not affine in any state.
TEST(ModelTest, StateBoundsAreAffineInTheirStateAndBoundOfReadsTheirLimit) {
  const Vehicle v = Bx15();
  const StateVector<double> x0 = SomeState(v, 40.0);
  for (int j = 0; j < kNumConstraints; ++j) {
    if (!IsStateBound(j)) {
      EXPECT_GT(ConstraintStateCount(j), 1) << kConstraintNames[j];
      continue;
    }
    EXPECT_EQ(ConstraintStateCount(j), 1) << kConstraintNames[j];
    const StateBound b = StateBoundOf(v, j, Curvy());
    EXPECT_TRUE(ConstraintUsesState(j, b.state)) << kConstraintNames[j];
    auto g_at = [&](double xi) {
      StateVector<double> x = x0;
      x[b.state] = xi;
      return StateConstraints(v, x, Curvy())[j];
    };
    const double scale = std::max(1.0, std::abs(b.value));
    EXPECT_NEAR(g_at(b.value), 0.0, 1e-12) << kConstraintNames[j];
    EXPECT_LT(g_at(b.value + (b.upper ? -0.1 : 0.1) * scale), 0.0) << kConstraintNames[j];
    EXPECT_GT(g_at(b.value + (b.upper ? 0.1 : -0.1) * scale), 0.0) << kConstraintNames[j];
    const double mid = g_at(b.value + 0.5 * scale);  // affine: the midpoint's value is the mean
    EXPECT_NEAR(mid, 0.5 * (g_at(b.value) + g_at(b.value + scale)), 1e-12) << kConstraintNames[j];
  }
  EXPECT_NEAR(StateBoundOf(v, kBorderRight, Curvy()).value, 0.5 * Curvy().width - v.border_margin,
              1e-12);
  EXPECT_FALSE(StateBoundOf(v, kCharge, Curvy()).upper);
  EXPECT_NEAR(StateBoundOf(v, kCharge, Curvy()).value, 0.0, 1e-12);
}

// Gravity in eq. 13a-c (lap/model/chassis.h) is the road frame's (x forward, y right, z down)
// g (-sin(sigma), sin(xi), cos(xi)) seen from the vehicle's frame, turned by alpha about z, with
// cos(sigma) ~ 1 as in the paper: from a road without slope and banking, each equation's constant
// part changes by -M times the change of its component (on the normal, from the paper's g).
TEST(ModelTest, GravityIsTheSlopedAndBankedRoadsInTheVehiclesFrame) {
  const Vehicle v = Bx15();
  const StateVector<double> x = SomeState(v, 25.0);  // alpha 0.03 rad
  RoadPoint flat = Curvy(), tilted = Curvy();
  flat.sigma = flat.xi = 0.0;
  tilted.sigma = 0.12;
  tilted.xi = -0.3;
  const Kinematics<double> k = ComputeKinematics(x, ControlVector<double>{0.0, 0.0}, flat);
  const ChassisLoads<double> loads{500.0, -800.0, 2500.0, 200.0, 10.0, x[kTauW], 5.0};
  const auto a = NewtonEuler(v, x, k, loads, flat), b = NewtonEuler(v, x, k, loads, tilted);
  const Eigen::Vector3d road_gravity(-std::sin(tilted.sigma), std::sin(tilted.xi), std::cos(tilted.xi));
  const Eigen::Vector3d vehicle_gravity =
      v.g * (Eigen::AngleAxisd(x[kAlpha], Eigen::Vector3d::UnitZ()).toRotationMatrix().transpose() * road_gravity);
  EXPECT_NEAR(b[0].c - a[0].c, -v.M * vehicle_gravity.x(), 1e-9 * v.M * v.g);
  EXPECT_NEAR(b[1].c - a[1].c, -v.M * vehicle_gravity.y(), 1e-9 * v.M * v.g);
  EXPECT_NEAR(b[2].c - a[2].c, -v.M * (vehicle_gravity.z() - v.g), 1e-9 * v.M * v.g);
}

TEST(ModelTest, StraightLevelCoastingDeceleratesByDragAndRolling) {
  const Vehicle v = Bx15();
  const RoadPoint road{};  // straight, level
  StateVector<double> x{};
  x[kV] = 40.0;
  x[kZ] = (v.M * v.g - v.lift_k * 1600.0) / v.K_s;
  x[kT] = 40.0;
  x[kE] = v.pack.e_i;
  const double R_e = v.r - x[kZ];
  x[kOmegaW] = 40.0 / R_e;  // no slip: F_x = 0
  const ModelPoint<double> m = EvaluateModel(v, x, ControlVector<double>{0.0, 0.0}, road);
  // Wheel torque zero, no slip: the chassis decelerates by drag only and the wheel by rolling.
  EXPECT_NEAR(m.acc[kVdot], -v.drag_k * 1600.0 / v.M, 1e-9);
  EXPECT_NEAR(m.tyre.N, v.M * v.g - v.lift_k * 1600.0, 1e-3 * v.M * v.g);
  EXPECT_NEAR(m.acc[kZddot], 0.0, 1e-2);
  EXPECT_NEAR(m.acc[kPhiddot], 0.0, 1e-12);  // upright: no roll moment
  EXPECT_NEAR(m.acc[kOmegaWdot], -m.tyre.tau_r / v.I_wy, 1e-9);
  EXPECT_NEAR(m.tyre.tau_r, v.mu_r * m.tyre.N * R_e, 1e-9);
  EXPECT_NEAR(m.dx_ds[kV], m.acc[kVdot] / 40.0, 1e-12);
}

TEST(ModelTest, EffortIsTheRidersWorkPerMetre) {
  // cost.h: (c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2 + c_r omega_phi^2) / sdot, by hand.
  Vehicle v = Bx15();
  v.roll_rate_weight = 0.03;
  const StateVector<double> x = SomeState(v, 30.0);
  const ControlVector<double> u{0.4, 500.0};
  const ModelPoint<double> m = EvaluateModel(v, x, u, Curvy());
  const double per_second = v.yaw_accel_weight * 0.16 + v.torque_rate_weight * 250000.0 +
                            0.03 * x[kOmegaPhi] * x[kOmegaPhi];
  EXPECT_NEAR(EffortPerMetre(v, x, u, m), per_second / m.kin.sdot, 1e-15);
  v.roll_rate_weight = 0.0;  // the paper's model: no price on rolling
  EXPECT_NEAR(EffortPerMetre(v, x, u, m), (per_second - 0.03 * 0.01) / m.kin.sdot, 1e-15);
}

TEST(ModelTest, SteadyLeanBalancesTheRollEquation) {
  // In a steady turn (no roll, yaw or slope change) eq. 14 reduces to a balance of gravity,
  // centrifugal and gyroscopic moments; at the lean angle that zeroes it, d2phi/dt2 must vanish.
  const Vehicle v = Bx15();
  RoadPoint road{};
  const double V = 20.0, R = 50.0, Oz = V / R;
  road.kappa = 1.0 / R;
  const double a = v.h - v.r_t;
  auto roll_acc = [&](double phi) {
    StateVector<double> x{};
    x[kV] = V;
    x[kZ] = v.M * v.g / v.K_s;
    x[kPhi] = phi;
    x[kT] = 40.0;
    x[kE] = v.pack.e_i;
    x[kOmegaW] = V / (v.r - v.r_t + std::cos(phi) * (v.r_t - x[kZ]));
    x[kOmegaZ] = Oz;
    return EvaluateModel(v, x, ControlVector<double>{0.0, 0.0}, road).acc[kPhiddot];
  };
  // Bisection for the equilibrium lean, then compare with the closed form of eq. 14-15 at z ~ 0:
  // M a (g sin(phi) - V Oz cos(phi)) - M r_t V Oz - I_gy w Oz cos(phi) + (I_yy - I_zz - M a^2)
  // cos(phi) sin(phi) Oz^2 + M a r_t sin(phi) Oz^2 ~ 0.
  double lo = 0.0, hi = 1.2;
  for (int i = 0; i < 80; ++i) ((roll_acc(lo) > 0) == (roll_acc(0.5 * (lo + hi)) > 0) ? lo : hi) =
      0.5 * (lo + hi);
  const double phi = 0.5 * (lo + hi);
  const double textbook = std::atan(V * Oz / v.g);
  EXPECT_GT(phi, textbook);  // the tyre's toroid and the gyroscopic moment both add lean
  EXPECT_LT(phi, textbook + 0.15);
  (void)a;
}

TEST(PowertrainTest, BatteryCurrentSolvesThePowerBalance) {
  const Vehicle v = Bx15();
  for (double tau_w : {50.0, 400.0, 900.0}) {
    const Powertrain<double> p = ComputePowertrain(v, tau_w, 150.0, 40.0, 50.0, 0.7 * v.pack.e_i);
    // eq. 23 with eq. 22a: V_mm i_m = eta_mc (V_bn - i_b R_b) i_b.
    EXPECT_NEAR(p.V_mm * p.i_m, v.eta_mc * (p.V_bn - p.i_b * v.pack.R_b) * p.i_b,
                1e-6 * p.V_mm * p.i_m);  // the smoothed discriminant (smooth.h) biases it by ~1e-7
    // The paper's eq. 32 (eta_m read as eta_mc, i_m = tau_e / k_tau) for the same motor power.
    const double R = v.pack.R_b, V = p.V_bn, eta = v.eta_mc;
    const double i_paper =
        V / (2 * R) - std::sqrt(eta * (V * V * eta - 4 * R * p.P_m)) / (2 * R * eta);
    EXPECT_NEAR(p.i_b, i_paper, 1e-6 * p.i_b);
    // Hand calculation of the motor side (eq. 24-26, 31).
    const double dT = 50.0 - v.motor.T_0;
    const double k_tau = v.motor.k_tau0 - v.motor.sigma_m * dT;
    // eq. 25 and 31: above the no-load current the shaft gives tau_e = k_tau (i_m - i_m0).
    const double i_m = tau_w / (v.eta_c * v.gamma_c * k_tau) + v.motor.i_m0;
    const double bias = 2.0 * 2.0 / (4.0 * i_m);  // of the smoothed positive part (smooth.h) [A]
    EXPECT_NEAR(p.i_m, i_m, 1.01 * bias);
    EXPECT_NEAR(p.tau_e, k_tau * (p.i_m - v.motor.i_m0), 1e-12 * p.tau_e);
    EXPECT_NEAR(p.tau_t, tau_w, v.eta_c * v.gamma_c * k_tau * 1.01 * bias);
    const double V_mm = (v.motor.k_V0 - v.motor.sigma_m * dT) * 150.0 * v.gamma_c +
                        (v.motor.R_m0 + v.motor.sigma_R * dT) * p.i_m;
    EXPECT_NEAR(p.V_mm, V_mm, 1e-9 * V_mm);
    EXPECT_NEAR(p.e_dot, -p.V_bn * p.i_b, 1e-9);
  }
}

TEST(PowertrainTest, BrakingDrawsNoCurrentAndTheMotorsFrictionDrags) {
  const Vehicle v = Bx15();
  const Powertrain<double> p = ComputePowertrain(v, -800.0, 150.0, 40.0, 50.0, v.pack.e_i);
  EXPECT_LT(std::abs(p.i_m), 0.05);
  const double k_tau = v.motor.k_tau0 - v.motor.sigma_m * (50.0 - v.motor.T_0);
  const double friction = v.eta_c * v.gamma_c * k_tau * v.motor.i_m0;  // at the wheel [N m]
  EXPECT_NEAR(p.tau_t, -friction, 1e-3);
  EXPECT_NEAR(p.tau_b, -800.0 + friction, 1e-3);
}

TEST(PowertrainTest, MotorCurrentIsConvexInTheWheelTorque) {
  // One minimum of H in tau_w needs i_m (and with it P_m, i_b, the losses) convex in tau_w.
  const Vehicle v = Bx15();
  auto i_m = [&](double tau_w) { return ComputePowertrain(v, tau_w, 150.0, 40.0, 50.0, v.pack.e_i).i_m; };
  for (double tau = -50.0; tau <= 50.0; tau += 0.5)
    EXPECT_GE(i_m(tau + 0.5) - 2.0 * i_m(tau) + i_m(tau - 0.5), -1e-9) << tau;
}

TEST(BarrierTest, IsC2AtTheJoin) {
  const double d = 1e-3;
  using J = ceres::Jet<ceres::Jet<double, 1>, 1>;
  auto eval = [&](double g) { return RelaxedBarrier(J(ceres::Jet<double, 1>(g, 0), 0), d); };
  const J left = eval(-d - 1e-12), right = eval(-d + 1e-12);
  EXPECT_NEAR(left.a.a, right.a.a, 1e-6);
  EXPECT_NEAR(left.v[0].a, right.v[0].a, 1e-3);
  EXPECT_NEAR(left.v[0].v[0], right.v[0].v[0], 1e-3 / (d * d));
}

}  // namespace
}  // namespace ttz::lap
