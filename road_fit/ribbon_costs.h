// Cost functors of the road-fit least-squares problem (paper eq. 4-8), templated for autodiff.
//
// Each functor is one term: the collocation defect of the dynamics (eq. 8), the control penalty
// U(u) (eq. 6b), the distance of a measured point to the ribbon's border (eq. 6a, 7), a measured
// width or banking, and the closure of a circuit. Those that read whole states or controls take
// the number N of states in the problem (ribbon.h: kLevelStates holds the banking at zero).
#pragma once

#include <array>
#include <cmath>

#include "road_fit/ribbon.h"

namespace ttz::road {

// Trapezoidal collocation defect of eq. 8 on one interval of length h [m] in zeta, with the
// interval's control u held constant:
//   (x1 - x0 - h/2 (g(x0, u) + g(x1, u))) / (h * tolerance_per_metre)
// so that a residual of 1 is a defect of `tolerance_per_metre` per metre of road.
template <int N = kNumRibbonStates>
struct DynamicsDefect {
  DynamicsDefect(double h, const RibbonScales& tolerance_per_metre) : h(h), tol(tolerance_per_metre) {}

  template <typename T>
  bool operator()(const T* x0, const T* x1, const T* u, T* r) const {
    T g0[N], g1[N];
    RibbonDerivative<N>(x0, u, g0);
    RibbonDerivative<N>(x1, u, g1);
    for (int j = 0; j < N; ++j)
      r[j] = (x1[j] - x0[j] - T(0.5 * h) * (g0[j] + g1[j])) / T(h * tol[j]);
    return true;
  }

  double h;
  RibbonScales tol;
};

// The smoothness term w_u U(u) of eq. 6b over an interval of length h, each control normalised by
// a reference magnitude so that one weight fits them all: sqrt(w h) u_j / u_ref_j, for the first M.
template <int M = kNumRibbonControls>
struct ControlEffort {
  ControlEffort(double weight_times_h, const std::array<double, kNumRibbonControls>& u_ref)
      : sqrt_wh(std::sqrt(weight_times_h)), u_ref(u_ref) {}

  template <typename T>
  bool operator()(const T* u, T* r) const {
    for (int j = 0; j < M; ++j) r[j] = T(sqrt_wh / u_ref[j]) * u[j];
    return true;
  }

  double sqrt_wh;
  std::array<double, kNumRibbonControls> u_ref;
};

// Side of the ribbon a measured point lies on: +1 left border, -1 right border, 0 centre line.
// Eq. 7 places the borders at +- r_w/2 across the road: along the horizontal left normal when the
// banking is zero (the paper's), along the banked surface's lateral axis (LeftAcross) otherwise.
template <int N = kNumRibbonStates, typename T>
void RibbonPoint(const T* x0, const T* x1, double t, double side, T* p) {
  T x[N];
  for (int j = 0; j < N; ++j) x[j] = (T(1.0) - T(t)) * x0[j] + T(t) * x1[j];
  T l[3];
  LeftAcross(x[kTheta], x[kSigma], BankingOf<N>(x), l);
  const T half = T(0.5 * side) * x[kWidth];
  p[0] = x[kX] + half * l[0];
  p[1] = x[kY] + half * l[1];
  p[2] = x[kZ] + half * l[2];
}

// Distance of a measured point to the ribbon point at fraction t of the interval (eq. 6a), in the
// road's frame: across the road, in elevation and along the road, each over its sigma_e. The
// along-road part pins the ribbon's abscissa (without it a ribbon could slide along itself); the
// point's fraction t is re-estimated by projection between solves, so it vanishes at the end.
template <int N = kNumRibbonStates>
struct BorderDistance {
  BorderDistance(double t, double side, const std::array<double, 3>& measured, const std::array<double, 3>& sigma_m)
      : t(t), side(side), p(measured), sigma(sigma_m) {}

  template <typename T>
  bool operator()(const T* x0, const T* x1, T* r) const {
    T b[3];
    RibbonPoint<N>(x0, x1, t, side, b);
    const T theta = (T(1.0) - T(t)) * x0[kTheta] + T(t) * x1[kTheta];
    T lx, ly;
    LeftNormal(theta, &lx, &ly);
    const T ex = T(p[0]) - b[0], ey = T(p[1]) - b[1];
    r[0] = (ex * lx + ey * ly) / T(sigma[0]);
    r[1] = (T(p[2]) - b[2]) / T(sigma[1]);
    r[2] = (ex * ly - ey * lx) / T(sigma[2]);
    return true;
  }

  double t, side;
  std::array<double, 3> p;
  std::array<double, 3> sigma;  // across [m], vertical [m], along [m]
};

// A measured state of centre-line inputs, the width r_w [m] or the banking xi [rad], against the
// state at fraction t of the interval, over its sigma (in the state's unit).
struct StateObservation {
  StateObservation(RibbonState state, double t, double measured, double sigma)
      : state(state), t(t), measured(measured), sigma(sigma) {}

  template <typename T>
  bool operator()(const T* x0, const T* x1, T* r) const {
    r[0] = ((T(1.0) - T(t)) * x0[state] + T(t) * x1[state] - T(measured)) / T(sigma);
    return true;
  }

  RibbonState state;
  double t, measured, sigma;
};

// A closed circuit ends where it starts: every state but s equal at both ends, the heading after
// `turns` full turns (mod 2 pi), each difference over its tolerance.
template <int N = kNumRibbonStates>
struct Closure {
  static constexpr int kNumResiduals = N - 1;  // all but s

  Closure(double turns, const RibbonScales& tolerance) : turns(turns), tol(tolerance) {}

  template <typename T>
  bool operator()(const T* first, const T* last, T* r) const {
    for (int j = 0, i = 0; j < N; ++j) {
      if (j == kS) continue;
      const double offset = j == kTheta ? 2.0 * M_PI * turns : 0.0;
      r[i++] = (last[j] - first[j] - T(offset)) / T(tol[j]);
    }
    return true;
  }

  double turns;
  RibbonScales tol;
};

}  // namespace ttz::road
