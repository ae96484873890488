// The second derivatives of the Hamiltonian that the indirect solver's Jacobian is built from
// (HyperDual numbers) against central differences of its first derivatives (plain Jets), and the
// control elimination: u* is a minimum of H and du*/dx matches differences of u*.
#include "lap/solver/node.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lap/testing/problem.h"

namespace ttz::lap {
namespace {

// The reference bike with a price on the roll rate, so every term of H is exercised.
Vehicle PricedRoll() {
  Vehicle v = testing::Bx15();
  v.roll_rate_weight = 0.03;
  return v;
}

struct Fixture {
  Vehicle v = PricedRoll();
  Scales sc = DefaultScales(v);
  RoadPoint road;
  BarrierWeight w{0.1, 1e-3};
  StateVector<double> xs, lambda;
  ControlVector<double> us = {2.0, 2.0};
  Fixture() {
    road.kappa = 0.008;
    road.dkappa = 1e-4;
    road.nu = 0.001;
    road.tau = -0.0005;
    road.sigma = 0.03;
    road.width = 8.0;
    const StateVector<double> x = {0.5, 0.02, 25.0, 0.005, 0.014, 0.15, 90.0, 45.0,
                                   0.8 * v.pack.e_i, 0.05, 0.01, 0.2, 150.0};
    for (int i = 0; i < kNumStates; ++i) {
      xs[i] = x[i] / sc.state[i];
      lambda[i] = 0.01 * ((i * 7) % 5 - 2);
    }
  }
};

TEST(NodeTest, HamiltonianSecondDerivativesMatchDifferencesOfFirst) {
  const Fixture f;
  constexpr int kZ = kNumStates + kNumControls;
  using J1 = ceres::Jet<double, kZ>;
  using J2 = ceres::Jet<J1, kZ>;
  std::array<double, kZ> z;
  std::copy(f.xs.begin(), f.xs.end(), z.begin());
  std::copy(f.us.begin(), f.us.end(), z.begin() + kNumStates);
  auto split = [](const auto& zz, auto* x, auto* u) {
    for (int i = 0; i < kNumStates; ++i) (*x)[i] = zz[i];
    for (int i = 0; i < kNumControls; ++i) (*u)[i] = zz[kNumStates + i];
  };
  std::array<J2, kZ> z2;
  for (int i = 0; i < kZ; ++i) z2[i] = J2(J1(z[i], i), i);
  StateVector<J2> x2;
  ControlVector<J2> u2;
  split(z2, &x2, &u2);
  const J2 H2 = EvaluateHamiltonian(f.v, f.sc, f.road, f.w, x2, u2, f.lambda).H;
  auto gradient = [&](const std::array<double, kZ>& zz) {
    std::array<J1, kZ> z1;
    for (int i = 0; i < kZ; ++i) z1[i] = J1(zz[i], i);
    StateVector<J1> x1;
    ControlVector<J1> u1;
    split(z1, &x1, &u1);
    return EvaluateHamiltonian(f.v, f.sc, f.road, f.w, x1, u1, f.lambda).H.v;
  };
  for (int j = 0; j < kZ; ++j) {
    auto zp = z, zm = z;
    const double h = 1e-6;
    zp[j] += h;
    zm[j] -= h;
    const auto gp = gradient(zp), gm = gradient(zm);
    for (int i = 0; i < kZ; ++i) {
      const double numeric = (gp[i] - gm[i]) / (2 * h);
      EXPECT_NEAR(H2.v[j].v[i], numeric, 1e-5 * std::abs(numeric) + 1e-9) << i << ", " << j;
    }
  }
}

TEST(NodeTest, EliminatedControlsMinimiseHAndTheirDerivativesMatchDifferences) {
  const Fixture f;
  NodeData d;
  d.u_start = f.us;
  EvaluateNode(f.v, f.sc, f.road, f.w, f.xs, f.lambda, true, &d);
  ASSERT_TRUE(d.valid);
  ASSERT_TRUE(d.control_converged);
  // A minimum: H grows in every direction around u*.
  auto H = [&](const ControlVector<double>& u) {
    return EvaluateHamiltonian(f.v, f.sc, f.road, f.w, f.xs, u, f.lambda).H;
  };
  for (double du0 : {-1e-3, 0.0, 1e-3})
    for (double du1 : {-1e-3, 0.0, 1e-3}) {
      if (du0 == 0.0 && du1 == 0.0) continue;
      EXPECT_GT(H({d.u[0] + du0, d.u[1] + du1}), H(d.u));
    }
  // du*/dx by the implicit-function theorem against differences of u*. The differences carry
  // the Newton's rounding floor (~1e-9 in u over a step of 2e-4), hence the absolute slack.
  for (int j = 0; j < kNumStates; ++j) {
    StateVector<double> xp = f.xs, xm = f.xs;
    xp[j] += 1e-4;
    xm[j] -= 1e-4;
    NodeData a = d, b = d;
    a.u_start = b.u_start = d.u;
    EvaluateNode(f.v, f.sc, f.road, f.w, xp, f.lambda, false, &a);
    EvaluateNode(f.v, f.sc, f.road, f.w, xm, f.lambda, false, &b);
    for (int i = 0; i < kNumControls; ++i) {
      const double numeric = (a.u[i] - b.u[i]) / 2e-4;
      EXPECT_NEAR(d.du_dx(i, j), numeric, 1e-3 * std::abs(numeric) + 2e-5) << i << ", " << j;
    }
  }
}

// H is quadratic in the controls (the yaw acceleration and the torque rate enter the state
// equations affinely, the rider's effort quadratically, no constraint at all), which the control
// elimination relies on: its one Newton step lands on u* from any start. Third differences of H
// along each control and a mixed direction, over steps as large as the controls' scales, vanish
// to rounding; a term of H cubic in a control would leave 6 a_3 d^3 there.
TEST(NodeTest, HIsQuadraticInTheControls) {
  const Fixture f;
  auto H = [&](const Eigen::Vector2d& u) {
    return EvaluateHamiltonian(f.v, f.sc, f.road, f.w, f.xs, {u[0], u[1]}, f.lambda).H;
  };
  const Eigen::Vector2d u0(f.us[0], f.us[1]);
  for (const Eigen::Vector2d& d : {Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0.0, 1.0),
                                   Eigen::Vector2d(0.7, -1.3)}) {
    const double third = H(u0 + 2 * d) - 3 * H(u0 + d) + 3 * H(u0) - H(u0 - d);
    const double second = H(u0 + d) - 2 * H(u0) + H(u0 - d);
    EXPECT_GT(std::abs(second), 1e-6 * std::abs(H(u0))) << d.transpose();  // it has curvature
    EXPECT_LT(std::abs(third), 1e-13 * std::abs(H(u0))) << d.transpose();
  }
}

// Where H is nearly flat in a control (here the yaw acceleration, its weight c_y a millionth of
// the reference's), a Newton step of 2e-6 (scaled) from u* lowers H by less than its rounding,
// so a line search on H would find no decrease (the damped Newton of sessions 52 and before had to
// take such a step for reducing |H_u|, docs/lap_log.md "Session 52"): the Newton from there ends
// where it ends from afar.
TEST(NodeTest, ControlsAreFoundWhereHIsNearlyFlatInOne) {
  Fixture f;
  f.v.yaw_accel_weight *= 1e-6;
  NodeData afar;
  afar.u_start = f.us;
  EvaluateNode(f.v, f.sc, f.road, f.w, f.xs, f.lambda, false, &afar);
  ASSERT_TRUE(afar.control_converged);
  // the premise: that step changes H by less than a line search on H can resolve
  const double H = EvaluateHamiltonian(f.v, f.sc, f.road, f.w, f.xs, afar.u, f.lambda).H;
  const double H_off = EvaluateHamiltonian(f.v, f.sc, f.road, f.w, f.xs, {afar.u[0] + 2e-6, afar.u[1]}, f.lambda).H;
  ASSERT_LT(std::abs(H_off - H), 1e-14 * std::abs(H));
  NodeData near = afar;
  near.u_start = {afar.u[0] + 2e-6, afar.u[1]};
  EvaluateNode(f.v, f.sc, f.road, f.w, f.xs, f.lambda, false, &near);
  EXPECT_TRUE(near.control_converged);
  EXPECT_NEAR(near.u[0], afar.u[0], 1e-9);
  EXPECT_NEAR(near.u[1], afar.u[1], 1e-9);
}

}  // namespace
}  // namespace ttz::lap
