// The road ribbon of the paper's section 2.1: states, controls and dynamics (eq. 5, 7, 8).
//
// Conventions (see docs/road_h5.md): local frame x east, y north, z up (metres); heading theta
// from east counter-clockwise; slope sigma positive uphill, dz/ds = sin(sigma). The paper's frame
// has z pointing down, hence its dz/dzeta = -sin(sigma) (eq. 8d); ours is the same road with z up.
// Banking xi is the third angle of eq. 2, T = R_z(theta) R_y(sigma) R_x(xi), which the paper sets
// to zero for want of data: here it is a state like sigma, with its rate and control, positive when
// the left border is the higher (the same sign in the paper's z-down frame). Inputs that do
// not carry it (RoadInput::carries_banking) hold it at zero (ribbon_fit.cc), as does --level.
#pragma once

#include <array>
#include <cmath>

namespace ttz::road {

// State x_t of eq. 5b, indexed along the estimated abscissa zeta.
enum RibbonState : int {
  kX = 0,         // x_t [m]
  kY,             // y_t [m]
  kZ,             // z_t [m]
  kTheta,         // heading theta [rad]
  kSigma,         // slope sigma [rad], positive uphill
  kThetaHat,      // theta-hat = dtheta/ds [1/m]
  kSigmaHat,      // sigma-hat = dsigma/ds [1/m]
  kWidth,         // r_w [m]
  kS,             // curvilinear abscissa s [m]
  kXi,            // banking xi [rad], positive when the left border is the higher
  kXiHat,         // xi-hat = dxi/ds [1/m]
  kNumRibbonStates
};

// One value per state, e.g. a tolerance or a scale.
using RibbonScales = std::array<double, kNumRibbonStates>;

// Control u_t of eq. 5a.
enum RibbonControl : int {
  kUTheta = 0,  // u_theta = d(theta-hat)/dzeta [1/m^2]
  kUSigma,      // u_sigma = d(sigma-hat)/dzeta [1/m^2]
  kUWidth,      // u_w = dr_w/dzeta [1]
  kUS,          // u_s: ds/dzeta = 1 + u_s [1]
  kUXi,         // u_xi = d(xi-hat)/dzeta [1/m^2]
  kNumRibbonControls
};

// A fit that holds the banking at zero leaves its states and control out of the problem, which
// is then the paper's exactly: its parameter blocks are the first kLevelStates states and
// kLevelControls controls of the same arrays (xi comes last for this). The functions and cost
// functors that read whole states take their count N, kLevelStates or kNumRibbonStates.
inline constexpr int kLevelStates = kXi;
inline constexpr int kLevelControls = kUXi;
constexpr int ControlsFor(int states) { return states == kNumRibbonStates ? kNumRibbonControls : kLevelControls; }

// xi of a state of N entries: zero when N leaves it out.
template <int N, typename T>
T BankingOf(const T* x) {
  static_assert(N == kLevelStates || N == kNumRibbonStates);
  if constexpr (N > kXi) return x[kXi];
  else return T(0.0);
}

// dx/dzeta = g(x, u), eq. 8a-8e (with z up: dz/dzeta = +sin(sigma)(1 + u_s)); xi follows the
// pattern of sigma. The first N states.
template <int N = kNumRibbonStates, typename T>
void RibbonDerivative(const T* x, const T* u, T* dx_dzeta) {
  using std::cos;
  using std::sin;
  const T stretch = T(1.0) + u[kUS];  // ds/dzeta, eq. 8e
  dx_dzeta[kX] = cos(x[kSigma]) * cos(x[kTheta]) * stretch;  // eq. 8d
  dx_dzeta[kY] = cos(x[kSigma]) * sin(x[kTheta]) * stretch;
  dx_dzeta[kZ] = sin(x[kSigma]) * stretch;
  dx_dzeta[kTheta] = x[kThetaHat] * stretch;  // eq. 8a
  dx_dzeta[kSigma] = x[kSigmaHat] * stretch;
  dx_dzeta[kThetaHat] = u[kUTheta];  // eq. 8b
  dx_dzeta[kSigmaHat] = u[kUSigma];
  dx_dzeta[kWidth] = u[kUWidth];  // eq. 8c
  dx_dzeta[kS] = stretch;         // eq. 8e
  if constexpr (N > kXi) {
    dx_dzeta[kXi] = x[kXiHat] * stretch;
    dx_dzeta[kXiHat] = u[kUXi];
  }
}

// Horizontal unit vector pointing to the left of the heading, in the x-y plane.
template <typename T>
void LeftNormal(const T& theta, T* lx, T* ly) {
  using std::cos;
  using std::sin;
  *lx = -sin(theta);
  *ly = cos(theta);
}

// The road's lateral unit vector, to the left across the (banked) road surface: the second column
// of T (eq. 2), cos(xi) times the horizontal left normal plus sin(xi) times the road's normal at
// zero banking, (-sin(sigma) cos(theta), -sin(sigma) sin(theta), cos(sigma)).
template <typename T>
void LeftAcross(const T& theta, const T& sigma, const T& xi, T* l) {
  using std::cos;
  using std::sin;
  l[0] = -cos(xi) * sin(theta) - sin(xi) * sin(sigma) * cos(theta);
  l[1] = cos(xi) * cos(theta) - sin(xi) * sin(sigma) * sin(theta);
  l[2] = sin(xi) * cos(sigma);
}

// Road-frame curvatures of eq. 12 in our z-up convention: the angular velocity per metre of
// T = R_z(theta) R_y(-sigma) R_x(xi) in its own (forward, left, up) axes is (tau, -nu, kappa), with
// kappa = cos(xi) cos(sigma) theta' + sin(xi) sigma' (positive turning left),
// nu = cos(xi) sigma' - sin(xi) cos(sigma) theta' (positive in a dip) and
// tau = sin(sigma) theta' + xi'. At xi = 0: kappa = cos(sigma) theta', nu = sigma'.
struct RibbonCurvatures {
  double kappa;
  double nu;
  double tau;
};
inline RibbonCurvatures Curvatures(double sigma, double xi, double theta_hat, double sigma_hat, double xi_hat) {
  const double turn = std::cos(sigma) * theta_hat;  // the heading's rate about the vertical, tilted by sigma
  return {std::cos(xi) * turn + std::sin(xi) * sigma_hat, std::cos(xi) * sigma_hat - std::sin(xi) * turn,
          std::sin(sigma) * theta_hat + xi_hat};
}

// The inverse of Curvatures for theta' and sigma', given xi, sigma and kappa, nu.
inline void HeadingAndSlopeRates(double sigma, double xi, double kappa, double nu, double* theta_hat,
                                 double* sigma_hat) {
  *theta_hat = (std::cos(xi) * kappa - std::sin(xi) * nu) / std::cos(sigma);
  *sigma_hat = std::sin(xi) * kappa + std::cos(xi) * nu;
}

}  // namespace ttz::road
