#include "lap/solver/collocation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ttz::lap {
namespace {

using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Matrix<double, 2, 1>;

// x' = lambda x.
struct Linear {
  double lambda;
  template <typename T>
  bool operator()(double, int, const Eigen::Matrix<T, 1, 1>& x, Eigen::Matrix<T, 1, 1>* dx) const {
    (*dx)[0] = lambda * x[0];
    return true;
  }
};

// The pendulum q'' = -sin q, as x = (q, q'): nonlinear, so Newton has work to do.
struct Pendulum {
  template <typename T>
  bool operator()(double, int, const Eigen::Matrix<T, 2, 1>& x, Eigen::Matrix<T, 2, 1>* dx) const {
    (*dx)[0] = x[1];
    (*dx)[1] = -sin(x[0]);
    return true;
  }
};

double LinearStep(const ButcherTableau& tab, double lambda, double h) {
  Vec1 x1(0.0);
  EXPECT_TRUE(CollocationStep<1>(tab, Linear{lambda}, 0.0, h, Vec1(1.0), Vec1(1.0), &x1));
  return x1[0];
}

TEST(CollocationTest, TableausAreConsistent) {
  for (const char* name : {"midpoint", "radau2", "radau3"}) {
    const ButcherTableau tab = TableauByName(name);
    double sum_b = 0.0;
    for (int j = 0; j < tab.Stages(); ++j) {
      double row = 0.0;
      for (double a : tab.A[j]) row += a;
      EXPECT_NEAR(row, tab.c[j], 1e-15) << name << " stage " << j;
      sum_b += tab.b[j];
    }
    EXPECT_NEAR(sum_b, 1.0, 1e-15) << name;
  }
  EXPECT_THROW(TableauByName("rk4"), std::invalid_argument);
}

// The local error of one step (x' = -x, and the pendulum) falls as h^(order + 1).
TEST(CollocationTest, LocalErrorFallsWithTheSchemesOrder) {
  for (const char* name : {"midpoint", "radau2", "radau3"}) {
    const ButcherTableau tab = TableauByName(name);
    double error[2];
    for (int k = 0; k < 2; ++k) {
      const double h = 0.1 / (1 << k);
      error[k] = std::abs(LinearStep(tab, -1.0, h) - std::exp(-h));
    }
    EXPECT_NEAR(std::log2(error[0] / error[1]), tab.order + 1, 0.2) << name;

    // The pendulum against many small steps of the same scheme.
    const Vec2 x0(1.0, 0.0), scale(1.0, 1.0);
    double perr[2];
    for (int k = 0; k < 2; ++k) {
      const double h = 0.2 / (1 << k);
      Vec2 coarse, fine = x0;
      ASSERT_TRUE(CollocationStep<2>(tab, Pendulum{}, 0.0, h, x0, scale, &coarse));
      for (int m = 0; m < 64; ++m) ASSERT_TRUE(CollocationStep<2>(tab, Pendulum{}, 0.0, h / 64, fine, scale, &fine));
      perr[k] = (coarse - fine).norm();
    }
    EXPECT_NEAR(std::log2(perr[0] / perr[1]), tab.order + 1, 0.3) << name;
  }
}

// On a stiff mode (h lambda = -1e4) the midpoint rule keeps almost all of it with its sign
// flipped; Radau IIA damps it (L-stability: R(z) ~ -2/z with two stages, -3/z with three).
TEST(CollocationTest, RadauDampsStiffModesTheMidpointRuleKeeps) {
  EXPECT_NEAR(LinearStep(ImplicitMidpoint(), -1e4, 1.0), -1.0, 1e-3);
  EXPECT_LT(std::abs(LinearStep(RadauIIA(2), -1e4, 1.0)), 1e-3);
  EXPECT_LT(std::abs(LinearStep(RadauIIA(3), -1e4, 1.0)), 1e-3);
}

TEST(CollocationTest, AnUndefinedRightHandSideFailsTheStep) {
  const auto undefined = [](double, int, const auto&, auto*) { return false; };
  Vec1 x1(0.0);
  EXPECT_FALSE(CollocationStep<1>(RadauIIA(3), undefined, 0.0, 0.1, Vec1(1.0), Vec1(1.0), &x1));
}

}  // namespace
}  // namespace ttz::lap
