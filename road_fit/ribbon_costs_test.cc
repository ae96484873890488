// Every cost functor of the road fit against numerical differentiation (ceres::GradientChecker).
#include "road_fit/ribbon_costs.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

namespace ttz::road {
namespace {

using State = std::array<double, kNumRibbonStates>;
using Control = std::array<double, kNumRibbonControls>;

// A plausible node: on a 3 % climb, turning left with radius ~80 m, 7 m wide, banked 3 degrees
// with the right border the higher and the banking growing.
State Node(double s) {
  return {120.0 + 0.9 * s, -40.0 + 0.4 * s, 30.0 + 0.03 * s, 0.4 + 0.0125 * s, 0.03, 0.0125 + 1e-4 * s, -2e-4, 7.0, s,
          -0.05 - 1e-3 * s, -1e-3};
}

// ceres::GradientChecker's own verdict is relative and fails on entries that are zero analytically
// (numerical noise ~1e-15); compare its two Jacobians with a relative tolerance above a floor.
void ExpectGradientsMatch(const ceres::CostFunction& cost, std::vector<double*> blocks) {
  ceres::NumericDiffOptions numeric;
  numeric.relative_step_size = 1e-7;
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::GradientChecker checker(&cost, no_manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(blocks.data(), 1e-7, &results);
  ASSERT_TRUE(results.return_value);
  for (size_t b = 0; b < results.jacobians.size(); ++b) {
    const auto& exact = results.jacobians[b];
    const auto& numerical = results.numeric_jacobians[b];
    for (int i = 0; i < exact.rows(); ++i)
      for (int j = 0; j < exact.cols(); ++j)
        EXPECT_NEAR(exact(i, j), numerical(i, j), 1e-6 * std::max(1.0, std::abs(exact(i, j))))
            << "block " << b << " residual " << i << " parameter " << j;
  }
}

TEST(RibbonCosts, DynamicsDefectGradient) {
  State x0 = Node(0.0), x1 = Node(1.3);
  Control u = {2e-4, -1e-5, 0.01, -0.002, 3e-5};
  RibbonScales tol = {1e-5, 1e-5, 1e-5, 1e-6, 1e-6, 1e-7, 1e-7, 1e-5, 1e-5, 1e-6, 1e-7};
  ceres::AutoDiffCostFunction<DynamicsDefect<>, kNumRibbonStates, kNumRibbonStates, kNumRibbonStates, kNumRibbonControls>
      cost(new DynamicsDefect<>(1.3, tol));
  ExpectGradientsMatch(cost, {x0.data(), x1.data(), u.data()});
}

TEST(RibbonCosts, DynamicsDefectVanishesOnAStraightClimb) {
  // A straight road at constant slope is an exact solution of eq. 8 with zero controls.
  const double sigma = 0.05, theta = 0.3, h = 2.0;
  State x0 = {0, 0, 0, theta, sigma, 0, 0, 6, 0};
  State x1 = {h * std::cos(sigma) * std::cos(theta), h * std::cos(sigma) * std::sin(theta), h * std::sin(sigma),
              theta, sigma, 0, 0, 6, h};
  Control u = {0, 0, 0, 0, 0};
  RibbonScales tol;
  tol.fill(1.0);
  double r[kNumRibbonStates];
  DynamicsDefect(h, tol)(x0.data(), x1.data(), u.data(), r);
  for (double v : r) EXPECT_NEAR(v, 0.0, 1e-14);
}

TEST(RibbonCosts, ControlEffortGradient) {
  Control u = {2e-4, -1e-5, 0.01, -0.002, 3e-5};
  ceres::AutoDiffCostFunction<ControlEffort<>, kNumRibbonControls, kNumRibbonControls> cost(
      new ControlEffort<>(2.0, {1e-3, 1e-4, 1e-2, 1e-2, 1e-4}));
  ExpectGradientsMatch(cost, {u.data()});
}

TEST(RibbonCosts, BorderDistanceGradientOnEachSide) {
  for (double side : {+1.0, -1.0, 0.0}) {
    State x0 = Node(10.0), x1 = Node(11.0);
    ceres::AutoDiffCostFunction<BorderDistance<>, 3, kNumRibbonStates, kNumRibbonStates> cost(
        new BorderDistance<>(0.37, side, {128.0, -32.0, 30.5}, {0.5, 1.0, 2.0}));
    ExpectGradientsMatch(cost, {x0.data(), x1.data()});
  }
}

TEST(RibbonCosts, BorderDistanceIsTheLateralOffsetOfTheBorder) {
  // Heading north: left is -x. A point 0.2 m outside the left border, 0.1 m above, 0.3 m ahead.
  State x0 = {0, 0, 10, M_PI / 2, 0, 0, 0, 6, 0}, x1 = {0, 1, 10, M_PI / 2, 0, 0, 0, 6, 1};
  double r[3];
  BorderDistance(0.5, +1.0, {-3.2, 0.8, 10.1}, {0.5, 1.0, 2.0})(x0.data(), x1.data(), r);
  EXPECT_NEAR(r[0], 0.2 / 0.5, 1e-12);
  EXPECT_NEAR(r[1], 0.1 / 1.0, 1e-12);
  EXPECT_NEAR(r[2], 0.3 / 2.0, 1e-12);
  BorderDistance(0.5, -1.0, {2.9, 0.5, 10.0}, {0.5, 1.0, 2.0})(x0.data(), x1.data(), r);  // 0.1 m inside the right border
  EXPECT_NEAR(r[0], 0.1 / 0.5, 1e-12);
}

TEST(RibbonCosts, BankingRaisesTheLeftBorderAndDrawsItIn) {
  // Heading east on the level, 6 m wide, banked 10 degrees with the left border the higher: the
  // left border is 3 sin(10 deg) m above the centre and 3 cos(10 deg) m left of it, the right one
  // as far below and right.
  const double xi = 10.0 * M_PI / 180.0;
  State x0 = {0, 0, 10, 0, 0, 0, 0, 6, 0, xi, 0}, x1 = {1, 0, 10, 0, 0, 0, 0, 6, 1, xi, 0};
  double left[3], right[3];
  RibbonPoint(x0.data(), x1.data(), 0.5, +1.0, left);
  RibbonPoint(x0.data(), x1.data(), 0.5, -1.0, right);
  EXPECT_NEAR(left[1], 3.0 * std::cos(xi), 1e-12);
  EXPECT_NEAR(left[2], 10.0 + 3.0 * std::sin(xi), 1e-12);
  EXPECT_NEAR(right[1], -3.0 * std::cos(xi), 1e-12);
  EXPECT_NEAR(right[2], 10.0 - 3.0 * std::sin(xi), 1e-12);
  // The lateral axis stays across the road on a slope: orthogonal to the tangent, unit length.
  const double theta = 0.7, sigma = 0.1;
  double l[3];
  LeftAcross(theta, sigma, xi, l);
  const double t[3] = {std::cos(sigma) * std::cos(theta), std::cos(sigma) * std::sin(theta), std::sin(sigma)};
  EXPECT_NEAR(l[0] * t[0] + l[1] * t[1] + l[2] * t[2], 0.0, 1e-15);
  EXPECT_NEAR(l[0] * l[0] + l[1] * l[1] + l[2] * l[2], 1.0, 1e-15);
}

TEST(RibbonCosts, CurvaturesAreTheRoadFramesAngularVelocity) {
  // The angular velocity per metre of T = R_z(theta) R_y(-sigma) R_x(xi), from central differences
  // of T along s, in T's own axes, is (tau, -nu, kappa) (road_fit/ribbon.h); and the inverse.
  const double theta0 = 0.3, sigma0 = 0.08, xi0 = -0.2, th = 0.012, sh = -3e-4, xh = 2e-3;
  const auto frame = [&](double s) {
    const Eigen::Matrix3d m = (Eigen::AngleAxisd(theta0 + th * s, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(-(sigma0 + sh * s), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(xi0 + xh * s, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    return m;
  };
  const double h = 1e-4;
  const Eigen::Matrix3d w = frame(0.0).transpose() * (frame(h) - frame(-h)) / (2 * h);  // skew
  const RibbonCurvatures c = Curvatures(sigma0, xi0, th, sh, xh);
  EXPECT_NEAR(w(2, 1), c.tau, 1e-9);
  EXPECT_NEAR(w(0, 2), -c.nu, 1e-9);
  EXPECT_NEAR(w(1, 0), c.kappa, 1e-9);
  double theta_hat, sigma_hat;
  HeadingAndSlopeRates(sigma0, xi0, c.kappa, c.nu, &theta_hat, &sigma_hat);
  EXPECT_NEAR(theta_hat, th, 1e-15);
  EXPECT_NEAR(sigma_hat, sh, 1e-15);
}

TEST(RibbonCosts, CentreDistanceIgnoresWidth) {
  State x0 = Node(10.0), x1 = Node(11.0);
  const BorderDistance<> centre(0.37, 0.0, {128.0, -32.0, 30.5}, {0.5, 1.0, 2.0});
  double a[3], b[3];
  centre(x0.data(), x1.data(), a);
  x0[kWidth] += 3.0;
  x1[kWidth] += 3.0;
  centre(x0.data(), x1.data(), b);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[i], b[i]);
}

TEST(RibbonCosts, StateObservationGradientAndValue) {
  State x0 = Node(0.0), x1 = Node(1.0);
  for (const auto& [state, measured, sigma] : {std::tuple{kWidth, 6.5, 0.5}, std::tuple{kXi, -0.1, 0.01}}) {
    ceres::AutoDiffCostFunction<StateObservation, 1, kNumRibbonStates, kNumRibbonStates> cost(
        new StateObservation(state, 0.25, measured, sigma));
    ExpectGradientsMatch(cost, {x0.data(), x1.data()});
    double r;
    StateObservation(state, 0.25, measured, sigma)(x0.data(), x1.data(), &r);
    EXPECT_NEAR(r, (0.75 * x0[state] + 0.25 * x1[state] - measured) / sigma, 1e-12) << state;
  }
}

TEST(RibbonCosts, ClosureGradientAndTurns) {
  State first = Node(0.0), last = Node(0.0);
  last[kTheta] += 2 * M_PI;
  last[kS] = 628.0;
  RibbonScales tol;
  tol.fill(1e-3);
  double r[Closure<>::kNumResiduals];
  Closure(1.0, tol)(first.data(), last.data(), r);
  for (double v : r) EXPECT_NEAR(v, 0.0, 1e-9);
  last[kX] += 0.5;
  ceres::AutoDiffCostFunction<Closure<>, Closure<>::kNumResiduals, kNumRibbonStates, kNumRibbonStates> cost(
      new Closure<>(1.0, tol));
  ExpectGradientsMatch(cost, {first.data(), last.data()});
}

}  // namespace
}  // namespace ttz::road
