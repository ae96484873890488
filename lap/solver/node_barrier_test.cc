// The node barrier of the indirect solver (node_barrier.h): its gradient against central
// differences of its value and its Hessian against central differences of its gradient, near a
// bend at a state inside every limit, the roll rate 5e-4 from its own (the barrier's relaxed branch).
#include "lap/solver/node_barrier.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lap/testing/problem.h"

namespace ttz::lap {
namespace {

TEST(NodeBarrierTest, GradientAndHessianMatchCentralDifferences) {
  const Vehicle v = testing::Bx15();
  const Scales sc = DefaultScales(v);
  RoadPoint road;
  road.kappa = 0.01;
  road.sigma = 0.02;
  road.width = 8.0;
  const BarrierWeight w{0.1, 1e-3};
  const double length_m = 4.0;
  StateVector<double> x = {1.5, 0.02, 30.0, 0.0, 0.014, 0.05, 100.0, 50.0,
                           0.7 * v.pack.e_i, 0.0, 0.0, 0.3, 200.0};
  x[kOmegaPhi] = 0.9995 * v.omega_phi_max;  // g = -5e-4 > -delta: the quadratic branch
  StateVector<double> xs;
  for (int i = 0; i < kNumStates; ++i) xs[i] = x[i] / sc.state[i];
  NodeBarrierData d;
  EvaluateNodeBarrier(v, sc, road, w, length_m, xs, true, &d);
  ASSERT_TRUE(d.valid);
  EXPECT_GT(NodeBarrierValue(v, sc, road, w, length_m, xs), 0.0);
  for (int j = 0; j < kNumStates; ++j) {
    const double h = 1e-6 * std::max(1.0, std::abs(xs[j]));
    StateVector<double> xp = xs, xm = xs;
    xp[j] += h;
    xm[j] -= h;
    const double grad = (NodeBarrierValue(v, sc, road, w, length_m, xp) -
                         NodeBarrierValue(v, sc, road, w, length_m, xm)) / (2 * h);
    EXPECT_NEAR(d.grad(j), grad, 1e-5 * std::abs(grad) + 1e-8) << j;
    NodeBarrierData a, b;
    EvaluateNodeBarrier(v, sc, road, w, length_m, xp, false, &a);
    EvaluateNodeBarrier(v, sc, road, w, length_m, xm, false, &b);
    ASSERT_TRUE(a.valid && b.valid);
    for (int i = 0; i < kNumStates; ++i) {
      const double numeric = (a.grad(i) - b.grad(i)) / (2 * h);
      EXPECT_NEAR(d.hess(i, j), numeric, 1e-5 * std::abs(numeric) + 1e-6) << i << ", " << j;
    }
  }
}

TEST(NodeBarrierTest, UndefinedWhereTheModelIs) {
  const Vehicle v = testing::Bx15();
  const Scales sc = DefaultScales(v);
  RoadPoint road;
  road.width = 8.0;
  StateVector<double> xs{};  // V = 0
  NodeBarrierData d;
  EvaluateNodeBarrier(v, sc, road, {0.1, 1e-3}, 4.0, xs, true, &d);
  EXPECT_FALSE(d.valid);
}

}  // namespace
}  // namespace ttz::lap
