// One-step collocation (implicit Runge-Kutta) schemes: their Butcher tableaux and one step of
// x' = f(s, x) by Newton's method on the stage equations, the Jacobian by Jets.
//
// What for: both solvers transcribe the lap by the implicit midpoint rule (the one-stage Gauss
// method, transcription.h); the re-simulation check (lap/resimulate.h) finds that at the
// pipelines' 0.5 s per interval its solutions miss the roll and the tyre's 4.2 Hz vertical mode
// (docs/lap.md "Re-simulation"). bench/collocation_bench measures what one step of a higher-order,
// L-stable scheme (Radau IIA) would miss on the same trajectories before a solver is built on it.
//
// Stage equations of an s-stage scheme (c, A, b) on [s_0, s_0 + h]:
//   X_j = x_0 + h sum_l A_jl f(s_0 + c_j h, X_l),   x_1 = x_0 + h sum_j b_j f(s_0 + c_j h, X_j).
#pragma once

#include <ceres/jet.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace ttz::lap {

struct ButcherTableau {
  std::string name;
  std::vector<double> c, b;               // nodes in [0, 1] and weights
  std::vector<std::vector<double>> A;     // stage coefficients, s x s
  int order = 0;                          // classical order (local error O(h^(order + 1)))
  int Stages() const { return static_cast<int>(c.size()); }
};

// The implicit midpoint rule: the one-stage Gauss method, order 2, A-stable but not L-stable
// (its stability function (1 + z/2) / (1 - z/2) tends to -1 for stiff modes).
ButcherTableau ImplicitMidpoint();
// Radau IIA with 2 (order 3) or 3 (order 5) stages: L-stable, stiffly accurate (x_1 = X_s).
// Hairer & Wanner, Solving ODEs II, table IV.5.5-6.
ButcherTableau RadauIIA(int stages);
// "midpoint", "radau2" or "radau3"; throws std::invalid_argument otherwise.
ButcherTableau TableauByName(const std::string& name);

struct CollocationStepOptions {
  int max_iterations = 30;
  // Newton stops when every stage's update is below this fraction of the state's scale.
  double tolerance = 1e-11;
};

// One step from (s0, x0) of length h. `rhs` is called as rhs(s, stage, x, &dx) with x and dx of
// Eigen::Matrix<T, N, 1> for T = double and T = ceres::Jet<double, N> (the stage index lets the
// caller hold its controls per stage) and returns false where f is undefined. `scale` (> 0) sets
// the Newton tolerance per state. Returns false when f is undefined at a Newton iterate, the
// iteration matrix is singular or Newton has not converged after max_iterations.
template <int N, class Rhs>
bool CollocationStep(const ButcherTableau& tab, const Rhs& rhs, double s0, double h,
                     const Eigen::Matrix<double, N, 1>& x0, const Eigen::Matrix<double, N, 1>& scale,
                     Eigen::Matrix<double, N, 1>* x1, const CollocationStepOptions& options = {}) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Jet = ceres::Jet<double, N>;
  const int S = tab.Stages(), n = N * S;
  Eigen::VectorXd Y(n);
  for (int j = 0; j < S; ++j) Y.segment<N>(j * N) = x0;
  std::vector<Vec> f(S);
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n);
    for (int l = 0; l < S; ++l) {
      Eigen::Matrix<Jet, N, 1> y, fy;
      for (int i = 0; i < N; ++i) y[i] = Jet(Y[l * N + i], i);
      if (!rhs(s0 + tab.c[l] * h, l, y, &fy)) return false;
      Eigen::Matrix<double, N, N> J;
      for (int i = 0; i < N; ++i) {
        f[l][i] = fy[i].a;
        J.row(i) = fy[i].v.transpose();
      }
      for (int j = 0; j < S; ++j) M.block<N, N>(j * N, l * N) -= h * tab.A[j][l] * J;
    }
    Eigen::VectorXd R(n);
    for (int j = 0; j < S; ++j) {
      Vec r = Y.segment<N>(j * N) - x0;
      for (int l = 0; l < S; ++l) r -= h * tab.A[j][l] * f[l];
      R.segment<N>(j * N) = r;
    }
    const Eigen::VectorXd d = M.partialPivLu().solve(-R);
    if (!d.allFinite()) return false;  // a singular iteration matrix
    Y += d;
    double largest = 0.0;
    for (int j = 0; j < S; ++j)
      largest = std::max(largest, (d.segment<N>(j * N).array() / scale.array()).abs().maxCoeff());
    if (largest < options.tolerance) {
      *x1 = x0;
      for (int j = 0; j < S; ++j) {
        Vec fj;
        if (!rhs(s0 + tab.c[j] * h, j, Vec(Y.segment<N>(j * N)), &fj)) return false;
        *x1 += h * tab.b[j] * fj;
      }
      return true;
    }
  }
  return false;
}

}  // namespace ttz::lap
