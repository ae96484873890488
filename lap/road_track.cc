#include "lap/road_track.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace ttz::lap {

RoadTrack::RoadTrack(const RoadArtefact& road, const std::string& name)
    : kappa_(road.kappa), nu_(road.nu), tau_(road.tau), sigma_(road.sigma), xi_(road.banking),
      width_(road.width),
      closed_(road.closed) {
  CheckAlongS(road, name, {"kappa", "nu", "tau", "sigma", "banking", "width"});
  const size_t n = road.s.size();
  ds_ = road.s[1] - road.s[0];
  for (size_t i = 1; i < n; ++i)
    if (!(std::abs(road.s[i] - road.s[i - 1] - ds_) <= 1e-6 * ds_))
      throw InputError(name, "dataset 's' is not uniformly spaced at sample " + std::to_string(i) +
                                 " (step " + std::to_string(road.s[i] - road.s[i - 1]) + " m, " +
                                 std::to_string(ds_) + " m expected, as road_fit writes it)");
  for (double& k : kappa_) k = -k;  // road.h5: left turn positive; model: right turn positive
  length_ = road.s.back() - road.s.front();
}

// Catmull-Rom (cubic Hermite with central-difference slopes) through uniform samples.
double RoadTrack::Sample(const std::vector<double>& f, double s, double* derivative) const {
  const int n = static_cast<int>(f.size());
  const double u = std::clamp(s, 0.0, length_) / ds_;
  const int i = std::clamp(static_cast<int>(std::floor(u)), 0, n - 2);
  const double t = u - i;
  auto at = [&](int j) { return f[std::clamp(j, 0, n - 1)]; };
  auto slope = [&](int j) {
    if (j <= 0) return at(1) - at(0);
    if (j >= n - 1) return at(n - 1) - at(n - 2);
    return 0.5 * (at(j + 1) - at(j - 1));
  };
  const double p0 = at(i), p1 = at(i + 1), m0 = slope(i), m1 = slope(i + 1);
  const double t2 = t * t, t3 = t2 * t;
  *derivative = ((6 * t2 - 6 * t) * p0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * p1 +
                 (3 * t2 - 2 * t) * m1) / ds_;
  return (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 +
         (t3 - t2) * m1;
}

RoadPoint RoadTrack::At(double s) const {
  RoadPoint p;
  double unused;
  p.s = s;
  p.kappa = Sample(kappa_, s, &p.dkappa);
  p.nu = Sample(nu_, s, &p.dnu);
  p.tau = Sample(tau_, s, &p.dtau);
  p.sigma = Sample(sigma_, s, &unused);
  p.xi = Sample(xi_, s, &unused);
  p.width = Sample(width_, s, &unused);
  return p;
}

}  // namespace ttz::lap
