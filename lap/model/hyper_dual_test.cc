// HyperDual (hyper_dual.h) against Ceres' nested Jets, which differentiate the same code to the
// same second order: every operation it defines, and the whole model with its constraints.
#include "lap/model/hyper_dual.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>

#include "lap/model/constraints.h"
#include "lap/model/dynamics.h"
#include "lap/testing/problem.h"

namespace ttz::lap {
namespace {

template <int N>
using Nested = ceres::Jet<ceres::Jet<double, N>, N>;

// Value, gradient and Hessian of a HyperDual equal a nested Jet's to `tol` relative.
template <int N>
void ExpectSame(const HyperDual<N>& h, const Nested<N>& j, double tol, const std::string& what) {
  auto near = [&](double a, double b, const std::string& part) {
    EXPECT_NEAR(a, b, tol * std::max(1.0, std::abs(b))) << what << " " << part;
  };
  near(h.a, j.a.a, "value");
  for (int i = 0; i < N; ++i) {
    near(h.g[i], j.v[i].a, "d/dz" + std::to_string(i));
    for (int k = 0; k < N; ++k)
      near(h.Hessian(i, k), j.v[i].v[k], "d2/dz" + std::to_string(i) + "dz" + std::to_string(k));
  }
}

// Every operation of hyper_dual.h in one function of three variables, in any scalar type.
template <typename T>
T EveryOperation(const T& x, const T& y, const T& z) {
  using std::cos;
  using std::log;
  using std::sin;
  using std::sqrt;
  T r = x * y - z / x + sqrt(x * x + y * y) * sin(z) - cos(x * z) + log(y + 3.0);
  r += 2.0 / (y + 4.0) - (1.5 - z) + (x + 0.5) * 3.0 - z / 7.0 + 0.25 * y - 1.0;
  T s = r;
  s *= x;
  s /= y + 5.0;
  s -= z;
  s = (s + 0.5 - 0.25) * 2.0 / 3.0;
  return -s + r * (x < y ? x : y) + (z >= 0.0 ? z : -z);
}

TEST(HyperDualTest, EveryOperationMatchesNestedJets) {
  const double at[3] = {0.7, -1.3, 0.4};
  std::array<HyperDual<3>, 3> h;
  std::array<Nested<3>, 3> j;
  for (int i = 0; i < 3; ++i) {
    h[i] = HyperDual<3>(at[i], i);
    j[i] = Nested<3>(ceres::Jet<double, 3>(at[i], i), i);
  }
  ExpectSame(EveryOperation(h[0], h[1], h[2]), EveryOperation(j[0], j[1], j[2]), 1e-13, "f");
  EXPECT_TRUE(!(h[0] < h[2]) && h[0] > 0.5 && 1.0 >= h[0] && h[1] != h[2]);
  EXPECT_EQ(Val(h[1]), at[1]);
  EXPECT_EQ(Cst<HyperDual<3>>(2.5).a, 2.5);
  EXPECT_EQ(Cst<HyperDual<3>>(2.5).g.squaredNorm() + Cst<HyperDual<3>>(2.5).h.squaredNorm(), 0.0);
}

// The model's state equations and constraints in HyperDual over (x, u), against nested Jets, at
// a state that exercises every part of it (braking and driving).
TEST(HyperDualTest, TheModelsSecondDerivativesMatchNestedJets) {
  constexpr int kZ = kNumStates + kNumControls;
  const Vehicle v = testing::Bx15();
  RoadPoint road;
  road.kappa = 0.01;
  road.nu = 0.002;
  road.tau = -0.001;
  road.dkappa = 1e-4;
  road.sigma = 0.05;
  road.width = 7.0;
  for (double tau_w : {300.0, -400.0}) {
    StateVector<double> x0 = {0.7, 0.03, 40.0, 0.01, v.M * v.g / v.K_s, 0.3, 40.0 / 0.29 * 1.02,
                              45.0, 0.6 * v.pack.e_i, 0.1, 0.01, 0.12, tau_w};
    const ControlVector<double> u0 = {0.5, 1500.0};
    StateVector<HyperDual<kZ>> xh;
    ControlVector<HyperDual<kZ>> uh;
    StateVector<Nested<kZ>> xj;
    ControlVector<Nested<kZ>> uj;
    for (int i = 0; i < kZ; ++i) {
      const double value = i < kNumStates ? x0[i] : u0[i - kNumStates];
      const HyperDual<kZ> h(value, i);
      const Nested<kZ> j(ceres::Jet<double, kZ>(value, i), i);
      if (i < kNumStates) {
        xh[i] = h;
        xj[i] = j;
      } else {
        uh[i - kNumStates] = h;
        uj[i - kNumStates] = j;
      }
    }
    const ModelPoint<HyperDual<kZ>> mh = EvaluateModel(v, xh, uh, road);
    const ModelPoint<Nested<kZ>> mj = EvaluateModel(v, xj, uj, road);
    for (int i = 0; i < kNumStates; ++i)
      ExpectSame(mh.dx_ds[i], mj.dx_ds[i], 1e-10, std::string("x'_") + kStateNames[i]);
    const ConstraintVector<HyperDual<kZ>> gh = EvaluateConstraints(v, xh, uh, road, mh);
    const ConstraintVector<Nested<kZ>> gj = EvaluateConstraints(v, xj, uj, road, mj);
    for (int c = 0; c < kNumConstraints; ++c) ExpectSame(gh[c], gj[c], 1e-10, kConstraintNames[c]);
  }
}

}  // namespace
}  // namespace ttz::lap
