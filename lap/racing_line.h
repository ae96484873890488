// A racing line for the initial guess: the path across the road of least squared curvature, the
// classic geometric stand-in for the fastest line (a path straighter than the centre line carries
// more speed through the same bend). The QSS lap on it (lap/qss.h) starts the solvers closer to
// the optimum where the optimum uses the road's width: on the TT course's fastest bends (20-22 km)
// the QSS on the centre line is 34 % slower than the optimal lap, and the indirect solver's first
// step from it stalls (docs/lap_log.md, "A racing line for the guess").
//
// On the mesh s_0 < ... < s_N with the lateral offset n_k (the model's n, right of the centre
// line positive, lap/model/state.h) as unknowns, the least-squares problem
//   minimise  sum_k w_k (kappa_k + n''_k)^2 + sum_k h_k L^2 ((kappa_p,k+1 - kappa_p,k) / h_k)^2,
//             w_k = (h_{k-1} + h_k) / 2, kappa_p = kappa + n''
//   subject to |n_k| <= share (width_k / 2 - border margin),  n_0 = the start state's offset
// with n''_k the second divided difference on the non-uniform mesh and kappa + n'' the path's
// curvature to first order in n and its slope (kappa right-turn positive, as the model's). Solved
// by Ceres with the bounds on the unknowns (a convex problem, solved from n_k = n_0 within the
// bounds: where its minimum is not unique, as on a straight, where every straight path is as good,
// that start decides).
#pragma once

#include <cmath>
#include <vector>

#include "lap/road_track.h"

namespace ttz::lap {

struct RacingLineOptions {
  // Share of the usable half width (width / 2 - the bike's border margin) that the line may use:
  // strictly inside, so the guess keeps a margin from the borders' barriers. Default 0.9.
  double width_share = 0.9;
  // L [m], the weight of the curvature's change against the curvature: without it the line
  // swaps a bend's curvature for abrupt changes of curvature, which the roll-rate limit (eq. 39b)
  // makes slower than the bend. Default 30 m.
  double curvature_change_length_m = 30.0;
  // n_0 [m], the offset of the start state: 0 for a lap (it starts on the centre line), the
  // previous window's offset for a window of the indirect solver's first step (lap/qss.h
  // ComputeQssFrom). Not bounded by the width share. Default 0.
  double start_offset_m = 0.0;
};

// The line at the mesh nodes.
struct RacingLine {
  std::vector<double> n;      // lateral offset, right positive [m]
  std::vector<double> dn_ds;  // its slope along the road [1]
  std::vector<double> kappa;  // the path's curvature, kappa / (1 - n kappa) + n'' [1/m]
};

// The racing line of `road` on `mesh` for a bike keeping `border_margin_m` from the borders.
RacingLine ComputeRacingLine(const RoadTrack& road, const std::vector<double>& mesh,
                             double border_margin_m, const RacingLineOptions& options = {});

// n'' at the middle of three nodes h_before and h_after apart (second divided difference).
template <typename T>
T SecondDifference(const T& n_before, const T& n, const T& n_after, double h_before, double h_after) {
  return 2.0 * ((n_after - n) / h_after - (n - n_before) / h_before) / (h_before + h_after);
}

// The residual of node k, sqrt(w_k) (kappa_k + n''_k), on parameters n_{k-1}, n_k, n_{k+1}
// (templated for automatic differentiation; public for its gradient check).
struct PathCurvatureResidual {
  double kappa;              // road curvature at s_k [1/m]
  double h_before, h_after;  // s_k - s_{k-1}, s_{k+1} - s_k [m]
  template <typename T>
  bool operator()(const T* n_before, const T* n, const T* n_after, T* residual) const {
    residual[0] = std::sqrt(0.5 * (h_before + h_after)) *
                  (kappa + SecondDifference(n_before[0], n[0], n_after[0], h_before, h_after));
    return true;
  }
};

// The residual of interval k, sqrt(h_k) L (kappa_p,k+1 - kappa_p,k) / h_k with kappa_p = kappa +
// n'', on n_{k-1} .. n_{k+2}: the change of the path's curvature, which the roll rate follows
// (|omega_phi| ~ V^3 |dkappa/ds| / g, eq. 39b; lap/qss.cc SpeedCap).
struct PathCurvatureChangeResidual {
  double kappa, kappa_next;          // road curvature at s_k, s_{k+1} [1/m]
  double h_before, h, h_after;       // s_k - s_{k-1}, s_{k+1} - s_k, s_{k+2} - s_{k+1} [m]
  double length_m;                   // L [m]
  template <typename T>
  bool operator()(const T* n0, const T* n1, const T* n2, const T* n3, T* residual) const {
    const T here = kappa + SecondDifference(n0[0], n1[0], n2[0], h_before, h);
    const T next = kappa_next + SecondDifference(n1[0], n2[0], n3[0], h, h_after);
    residual[0] = std::sqrt(h) * length_m * (next - here) / h;
    return true;
  }
};

}  // namespace ttz::lap
