#include "road_fit/road_profile.h"

#include <algorithm>
#include <cmath>

namespace ttz::road {
namespace {

using State = std::array<double, kNumRibbonStates>;

// Integrates eq. 8 over `dzeta` from x under control u with classical RK4 in `steps` steps.
State Integrate(State x, const std::array<double, kNumRibbonControls>& u, double dzeta, int steps) {
  const double h = dzeta / steps;
  auto add = [](const State& a, const State& b, double f) {
    State c;
    for (int j = 0; j < kNumRibbonStates; ++j) c[j] = a[j] + f * b[j];
    return c;
  };
  for (int i = 0; i < steps; ++i) {
    State k1, k2, k3, k4;
    RibbonDerivative(x.data(), u.data(), k1.data());
    const State x2 = add(x, k1, h / 2);
    RibbonDerivative(x2.data(), u.data(), k2.data());
    const State x3 = add(x, k2, h / 2);
    RibbonDerivative(x3.data(), u.data(), k3.data());
    const State x4 = add(x, k3, h);
    RibbonDerivative(x4.data(), u.data(), k4.data());
    for (int j = 0; j < kNumRibbonStates; ++j) x[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  return x;
}

void Append(const State& x, double s, RoadProfile* p) {
  const RibbonCurvatures c = Curvatures(x[kSigma], x[kXi], x[kThetaHat], x[kSigmaHat], x[kXiHat]);
  p->s.push_back(s);
  p->x.push_back(x[kX]);
  p->y.push_back(x[kY]);
  p->z.push_back(x[kZ]);
  p->theta.push_back(x[kTheta]);
  p->sigma.push_back(x[kSigma]);
  p->width.push_back(x[kWidth]);
  p->banking.push_back(x[kXi]);
  p->kappa.push_back(c.kappa);
  p->nu.push_back(c.nu);
  p->tau.push_back(c.tau);
}

}  // namespace

RoadProfile SampleRibbon(const Ribbon& ribbon, double ds_m) {
  RoadProfile profile;
  profile.closed = ribbon.closed;
  const double s0 = ribbon.x.front()[kS];
  const double length = ribbon.length();
  const long m = std::max(1L, std::lround(length / ds_m));
  profile.ds_m = length / m;
  size_t k = 0;
  for (long j = 0; j <= m; ++j) {
    const double s = j == m ? length : j * profile.ds_m;
    while (k + 1 < ribbon.u.size() && ribbon.x[k + 1][kS] - s0 <= s) ++k;
    const double stretch = 1.0 + ribbon.u[k][kUS];  // ds/dzeta on the interval, eq. 8e
    const double dzeta = std::max(0.0, (s - (ribbon.x[k][kS] - s0)) / stretch);
    State x = Integrate(ribbon.x[k], ribbon.u[k], dzeta, 4);
    Append(x, s, &profile);
  }
  return profile;
}

Ribbon RibbonFromProfile(const RoadProfile& p) {
  Ribbon ribbon;
  ribbon.h = p.ds_m;
  ribbon.closed = p.closed;
  const size_t n = p.s.size();
  ribbon.x.resize(n);
  for (size_t k = 0; k < n; ++k) {
    double theta_hat, sigma_hat;
    HeadingAndSlopeRates(p.sigma[k], p.banking[k], p.kappa[k], p.nu[k], &theta_hat, &sigma_hat);  // eq. 12
    const double xi_hat = p.tau[k] - std::sin(p.sigma[k]) * theta_hat;
    ribbon.x[k] = {p.x[k], p.y[k],  p.z[k], p.theta[k], p.sigma[k], theta_hat, sigma_hat, p.width[k],
                   p.s[k], p.banking[k], xi_hat};
  }
  SetControlsFromStates(&ribbon);
  return ribbon;
}

}  // namespace ttz::road
