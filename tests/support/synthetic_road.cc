#include "tests/support/synthetic_road.h"

#include <cmath>
#include <limits>
#include <random>

#include "road_fit/ribbon.h"

namespace ttz::testing {

RoadSpec ClimbingCurve() {
  return {"climbing curve", 1000.0, false,
          [](double s) { return 0.0105 + 0.0085 * std::sin(2 * M_PI * s / 400.0); },
          [](double s) { return 0.05 + 0.02 * std::sin(2 * M_PI * s / 300.0); },
          [](double s) { return 7.0 + std::sin(2 * M_PI * s / 500.0); }};
}

RoadSpec ClothoidSBend() {
  // Curvature breakpoints (s, kappa): piecewise linear between them.
  static const std::vector<std::pair<double, double>> k = {
      {0, 0}, {100, 0}, {160, 1.0 / 40}, {210, 1.0 / 40}, {330, -1.0 / 40}, {380, -1.0 / 40}, {440, 0}, {600, 0}};
  auto kappa = [](double s) {
    for (size_t i = 1; i < k.size(); ++i)
      if (s <= k[i].first) {
        const double t = (s - k[i - 1].first) / (k[i].first - k[i - 1].first);
        return (1 - t) * k[i - 1].second + t * k[i].second;
      }
    return 0.0;
  };
  const double slope = std::atan(0.06);
  return {"clothoid S-bend", 600.0, false, [=](double s) { return kappa(s) / std::cos(slope); },
          [=](double) { return slope; }, [](double) { return 6.0; }};
}

RoadSpec Circle() {
  const double radius = 100.0;
  return {"circle", 2 * M_PI * radius, true, [=](double) { return 1.0 / radius; }, [](double) { return 0.0; },
          [](double) { return 8.0; }};
}

RoadSpec BankedClimbingCurve() {
  RoadSpec spec = ClimbingCurve();
  spec.name = "banked climbing curve";
  const auto turn = spec.heading_rate;
  spec.banking = [=](double s) { return -0.16 * turn(s) / 0.019; };
  return spec;
}

TrueRoad Integrate(const RoadSpec& spec, double step_m) {
  TrueRoad r;
  r.closed = spec.closed;
  const long n = std::lround(spec.length_m / step_m);
  const double h = spec.length_m / n;
  // State (x, y, z, theta); sigma is given, theta' is given: dx/ds = cos(sigma) cos(theta), ...
  auto f = [&](double s, const std::array<double, 4>& q) {
    const double sg = spec.slope(s);
    return std::array<double, 4>{std::cos(sg) * std::cos(q[3]), std::cos(sg) * std::sin(q[3]), std::sin(sg),
                                 spec.heading_rate(s)};
  };
  std::array<double, 4> q = {0, 0, 0, 0};
  for (long i = 0; i <= n; ++i) {
    const double s = i * h;
    r.s.push_back(s);
    r.x.push_back(q[0]);
    r.y.push_back(q[1]);
    r.z.push_back(q[2]);
    r.theta.push_back(q[3]);
    r.sigma.push_back(spec.slope(s));
    const double xi = spec.banking(s), d = 1e-3;
    const double slope_rate = (spec.slope(s + d) - spec.slope(s - d)) / (2 * d);
    r.kappa.push_back(road::Curvatures(spec.slope(s), xi, spec.heading_rate(s), slope_rate, 0.0).kappa);
    r.width.push_back(spec.width(s));
    r.banking.push_back(xi);
    auto add = [](const std::array<double, 4>& a, const std::array<double, 4>& b, double c) {
      return std::array<double, 4>{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]};
    };
    const auto k1 = f(s, q), k2 = f(s + h / 2, add(q, k1, h / 2)), k3 = f(s + h / 2, add(q, k2, h / 2)),
               k4 = f(s + h, add(q, k3, h));
    for (int j = 0; j < 4; ++j) q[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  return r;
}

size_t TrueRoad::Nearest(double px, double py) const {
  size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < s.size(); ++i) {
    const double d = std::hypot(x[i] - px, y[i] - py);
    if (d < best_d) best_d = d, best = i;
  }
  return best;
}

road::RoadInput SampleBorders(const TrueRoad& road, const SamplingOptions& options) {
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> spacing(options.min_spacing_m, options.max_spacing_m);
  std::normal_distribution<double> noise(0.0, options.noise_sd_m);
  road::RoadInput input;
  input.file = "synthetic";
  input.format = "border-points";
  input.has_elevation = true;
  input.carries_banking = true;
  const double step = road.s[1] - road.s[0];
  // A closed road ends one spacing short of its start, as a survey of a circuit would.
  const double end = road.closed ? road.length() - options.max_spacing_m : road.length();
  for (road::Side side : {road::Side::kLeft, road::Side::kRight}) {
    const double sign = side == road::Side::kLeft ? 1.0 : -1.0;
    for (double s = 0.5 * spacing(rng); s <= end; s += spacing(rng)) {
      const size_t i = std::min(road.s.size() - 1, static_cast<size_t>(std::lround(s / step)));
      const double half = 0.5 * sign * road.width[i];
      double l[3];
      road::LeftAcross(road.theta[i], road.sigma[i], road.banking[i], l);
      road::Observation o;
      o.side = side;
      o.x_m = road.x[i] + half * l[0] + noise(rng);
      o.y_m = road.y[i] + half * l[1] + noise(rng);
      o.z_m = road.z[i] + half * l[2] + noise(rng);
      o.line = static_cast<long>(input.points.size()) + 2;
      input.points.push_back(o);
    }
  }
  return input;
}

}  // namespace ttz::testing
