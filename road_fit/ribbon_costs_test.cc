// Every cost functor of the road fit against numerical differentiation (ceres::GradientChecker).
#include "road_fit/ribbon_costs.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ttz::road {
namespace {

using State = std::array<double, kNumRibbonStates>;
using Control = std::array<double, kNumRibbonControls>;

// A plausible node: on a 3 % climb, turning left with radius ~80 m, 7 m wide.
State Node(double s) {
  return {120.0 + 0.9 * s, -40.0 + 0.4 * s, 30.0 + 0.03 * s, 0.4 + 0.0125 * s, 0.03, 0.0125 + 1e-4 * s, -2e-4, 7.0, s};
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
  Control u = {2e-4, -1e-5, 0.01, -0.002};
  RibbonScales tol = {1e-5, 1e-5, 1e-5, 1e-6, 1e-6, 1e-7, 1e-7, 1e-5, 1e-5};
  ceres::AutoDiffCostFunction<DynamicsDefect, kNumRibbonStates, kNumRibbonStates, kNumRibbonStates, kNumRibbonControls>
      cost(new DynamicsDefect(1.3, tol));
  ExpectGradientsMatch(cost, {x0.data(), x1.data(), u.data()});
}

TEST(RibbonCosts, DynamicsDefectVanishesOnAStraightClimb) {
  // A straight road at constant slope is an exact solution of eq. 8 with zero controls.
  const double sigma = 0.05, theta = 0.3, h = 2.0;
  State x0 = {0, 0, 0, theta, sigma, 0, 0, 6, 0};
  State x1 = {h * std::cos(sigma) * std::cos(theta), h * std::cos(sigma) * std::sin(theta), h * std::sin(sigma),
              theta, sigma, 0, 0, 6, h};
  Control u = {0, 0, 0, 0};
  RibbonScales tol;
  tol.fill(1.0);
  double r[kNumRibbonStates];
  DynamicsDefect(h, tol)(x0.data(), x1.data(), u.data(), r);
  for (double v : r) EXPECT_NEAR(v, 0.0, 1e-14);
}

TEST(RibbonCosts, ControlEffortGradient) {
  Control u = {2e-4, -1e-5, 0.01, -0.002};
  ceres::AutoDiffCostFunction<ControlEffort, kNumRibbonControls, kNumRibbonControls> cost(
      new ControlEffort(2.0, {1e-3, 1e-4, 1e-2, 1e-2}));
  ExpectGradientsMatch(cost, {u.data()});
}

TEST(RibbonCosts, BorderDistanceGradientOnEachSide) {
  for (double side : {+1.0, -1.0, 0.0}) {
    State x0 = Node(10.0), x1 = Node(11.0);
    ceres::AutoDiffCostFunction<BorderDistance, 3, kNumRibbonStates, kNumRibbonStates> cost(
        new BorderDistance(0.37, side, {128.0, -32.0, 30.5}, {0.5, 1.0, 2.0}));
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

TEST(RibbonCosts, CentreDistanceIgnoresWidth) {
  State x0 = Node(10.0), x1 = Node(11.0);
  const BorderDistance centre(0.37, 0.0, {128.0, -32.0, 30.5}, {0.5, 1.0, 2.0});
  double a[3], b[3];
  centre(x0.data(), x1.data(), a);
  x0[kWidth] += 3.0;
  x1[kWidth] += 3.0;
  centre(x0.data(), x1.data(), b);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[i], b[i]);
}

TEST(RibbonCosts, WidthObservationGradient) {
  State x0 = Node(0.0), x1 = Node(1.0);
  ceres::AutoDiffCostFunction<WidthObservation, 1, kNumRibbonStates, kNumRibbonStates> cost(
      new WidthObservation(0.25, 6.5, 0.5));
  ExpectGradientsMatch(cost, {x0.data(), x1.data()});
}

TEST(RibbonCosts, ClosureGradientAndTurns) {
  State first = Node(0.0), last = Node(0.0);
  last[kTheta] += 2 * M_PI;
  last[kS] = 628.0;
  RibbonScales tol;
  tol.fill(1e-3);
  double r[kS];
  Closure(1.0, tol)(first.data(), last.data(), r);
  for (double v : r) EXPECT_NEAR(v, 0.0, 1e-9);
  last[kX] += 0.5;
  ceres::AutoDiffCostFunction<Closure, kS, kNumRibbonStates, kNumRibbonStates> cost(new Closure(1.0, tol));
  ExpectGradientsMatch(cost, {first.data(), last.data()});
}

}  // namespace
}  // namespace ttz::road
