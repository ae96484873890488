// The road ribbon of the paper's section 2.1: states, controls and dynamics (eq. 5, 7, 8).
//
// Conventions (see docs/road_h5.md): local frame x east, y north, z up (metres); heading theta
// from east counter-clockwise; slope sigma positive uphill, dz/ds = sin(sigma). The paper's frame
// has z pointing down, hence its dz/dzeta = -sin(sigma) (eq. 8d); ours is the same road with z up.
// Banking is zero (paper: xi = 0).
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
  kNumRibbonControls
};

// dx/dzeta = g(x, u), eq. 8a-8e (with z up: dz/dzeta = +sin(sigma)(1 + u_s)).
template <typename T>
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
}

// Lateral unit vector pointing to the left of the heading, in the x-y plane (no banking).
template <typename T>
void LeftNormal(const T& theta, T* lx, T* ly) {
  using std::cos;
  using std::sin;
  *lx = -sin(theta);
  *ly = cos(theta);
}

// Road-frame curvatures of eq. 12 in our z-up convention, from heading rate and slope:
// kappa = cos(sigma) dtheta/ds (positive turning left), nu = dsigma/ds (positive where the slope
// increases, a dip), tau = sin(sigma) dtheta/ds.
struct RibbonCurvatures {
  double kappa;
  double nu;
  double tau;
};
inline RibbonCurvatures Curvatures(double sigma, double theta_hat, double sigma_hat) {
  return {std::cos(sigma) * theta_hat, sigma_hat, std::sin(sigma) * theta_hat};
}

}  // namespace ttz::road
