#include "road_fit/initial_guess.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "road_fit/station.h"

namespace ttz::road {
namespace {

constexpr double kPositionSmoothingM = 5.0;  // half-width of the moving average of positions
constexpr double kRateSmoothingM = 10.0;     // half-width of the moving average of angle rates

using Series = std::vector<double>;

// Moving average over +- half nodes; a closed series (node N = node 0) wraps, an open one shrinks
// its window at the ends.
Series MovingAverage(const Series& v, long half, bool closed) {
  const long n = static_cast<long>(v.size()) - (closed ? 1 : 0);
  Series out(v.size());
  for (long k = 0; k < n; ++k) {
    double sum = 0.0;
    long count = 0;
    for (long j = k - half; j <= k + half; ++j) {
      if (!closed && (j < 0 || j >= n)) continue;
      sum += v[((j % n) + n) % n];
      ++count;
    }
    out[k] = sum / count;
  }
  if (closed) out[n] = out[0];
  return out;
}

// dv/dzeta by central differences (one-sided at the ends of an open series). `period` is added
// when a closed series wraps (2 pi turns for the heading, 0 otherwise).
Series Derivative(const Series& v, double h, bool closed, double period = 0.0) {
  const long n = static_cast<long>(v.size()) - (closed ? 1 : 0);
  Series d(v.size());
  for (long k = 0; k < n; ++k) {
    if (closed) {
      const double next = k + 1 < n ? v[k + 1] : v[0] + period;
      const double prev = k > 0 ? v[k - 1] : v[n - 1] - period;
      d[k] = (next - prev) / (2.0 * h);
    } else {
      const long a = std::max(k - 1, 0L), b = std::min(k + 1, n - 1);
      d[k] = (v[b] - v[a]) / ((b - a) * h);
    }
  }
  if (closed) d[n] = d[0];
  return d;
}

// Isolated far outlier: far from both neighbours while they are close to each other.
bool IsSpike(const std::array<double, 3>& prev, const std::array<double, 3>& p, const std::array<double, 3>& next) {
  const auto dist = [](const auto& a, const auto& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); };
  const double d_prev = dist(prev, p), d_next = dist(p, next);
  return std::min(d_prev, d_next) > 100.0 && d_prev + d_next > 10.0 * dist(prev, next);
}

std::vector<std::array<double, 3>> SideWithoutSpikes(const RoadInput& input, Side side) {
  std::vector<std::array<double, 3>> all, kept;
  for (const Observation& o : input.points)
    if (o.side == side) all.push_back({o.x_m, o.y_m, o.z_m});
  for (size_t i = 0; i < all.size(); ++i)
    if (i == 0 || i + 1 == all.size() || !IsSpike(all[i - 1], all[i], all[i + 1])) kept.push_back(all[i]);
  return kept;
}

CentrePolyline CentreOfBorders(const RoadInput& input) {
  const auto left = SideWithoutSpikes(input, Side::kLeft);
  const auto right = SideWithoutSpikes(input, Side::kRight);
  std::vector<PointXY> right_xy, left_xy;
  for (const auto& p : right) right_xy.push_back({p[0], p[1]});
  for (const auto& p : left) left_xy.push_back({p[0], p[1]});
  const bool closed = std::hypot(right.front()[0] - right.back()[0], right.front()[1] - right.back()[1]) < 30.0;
  const std::vector<Station> match = ProjectOntoPolyline(right_xy, closed, left_xy);
  CentrePolyline centre;
  for (size_t i = 0; i < left.size(); ++i) {
    const auto& a = right[match[i].interval];
    const auto& b = right[(match[i].interval + 1) % right.size()];
    const double t = match[i].t;
    std::array<double, 3> mid;
    for (int j = 0; j < 3; ++j) mid[j] = 0.5 * (left[i][j] + (1.0 - t) * a[j] + t * b[j]);
    centre.p.push_back(mid);
    centre.width_m.push_back(2.0 * match[i].distance_m);
  }
  return centre;
}

CentrePolyline CentreOfCentreLine(const RoadInput& input) {
  CentrePolyline centre;
  for (const Observation& o : input.points) {
    centre.p.push_back({o.x_m, o.y_m, o.z_m});
    centre.width_m.push_back(o.width_m);
  }
  return centre;
}

}  // namespace

CentrePolyline RoughCentre(const RoadInput& input) {
  const bool borders = std::any_of(input.points.begin(), input.points.end(),
                                   [](const Observation& o) { return o.side != Side::kCentre; });
  return borders ? CentreOfBorders(input) : CentreOfCentreLine(input);
}

double EndsGap(const CentrePolyline& centre) {
  const auto& a = centre.p.front();
  const auto& b = centre.p.back();
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

Ribbon InitialRibbon(const CentrePolyline& centre_in, double ds_m, bool closed) {
  CentrePolyline centre = centre_in;
  if (closed) {  // the closing segment back to the start
    centre.p.push_back(centre.p.front());
    centre.width_m.push_back(centre.width_m.front());
  }
  Series zeta(centre.p.size(), 0.0);
  for (size_t i = 1; i < centre.p.size(); ++i) {
    const auto& a = centre.p[i - 1];
    const auto& b = centre.p[i];
    zeta[i] = zeta[i - 1] + std::sqrt(std::pow(b[0] - a[0], 2) + std::pow(b[1] - a[1], 2) + std::pow(b[2] - a[2], 2));
  }
  const double length = zeta.back();
  const long n = std::lround(length / ds_m);
  if (n < 4) throw InputError("", "the road is " + std::to_string(length) + " m long: too short for a node spacing of " +
                                      std::to_string(ds_m) + " m (at least 4 intervals expected)");
  Ribbon ribbon;
  ribbon.h = length / n;
  ribbon.closed = closed;

  // Resample position and width at zeta_k = k h.
  std::array<Series, 3> pos;
  Series width(n + 1);
  for (auto& c : pos) c.resize(n + 1);
  size_t seg = 0;
  for (long k = 0; k <= n; ++k) {
    const double z = std::min(k * ribbon.h, length);
    while (seg + 2 < zeta.size() && zeta[seg + 1] < z) ++seg;
    const double span = zeta[seg + 1] - zeta[seg];
    const double t = span > 0 ? std::clamp((z - zeta[seg]) / span, 0.0, 1.0) : 0.0;
    for (int j = 0; j < 3; ++j) pos[j][k] = (1 - t) * centre.p[seg][j] + t * centre.p[seg + 1][j];
    width[k] = (1 - t) * centre.width_m[seg] + t * centre.width_m[seg + 1];
  }
  const long half_pos = std::max(1L, std::lround(kPositionSmoothingM / ribbon.h));
  const long half_rate = std::max(1L, std::lround(kRateSmoothingM / ribbon.h));
  for (auto& c : pos) c = MovingAverage(c, half_pos, closed);
  width = MovingAverage(width, half_rate, closed);

  // Heading (unwrapped) and slope from the smoothed positions.
  const Series dx = Derivative(pos[0], ribbon.h, closed), dy = Derivative(pos[1], ribbon.h, closed);
  const Series dz = Derivative(pos[2], ribbon.h, closed);
  Series theta(n + 1), sigma(n + 1);
  for (long k = 0; k <= n; ++k) {
    theta[k] = std::atan2(dy[k], dx[k]);
    if (k > 0) theta[k] += 2.0 * M_PI * std::round((theta[k - 1] - theta[k]) / (2.0 * M_PI));
    sigma[k] = std::atan2(dz[k], std::hypot(dx[k], dy[k]));
  }
  const double turns = closed ? std::round((theta[n] - theta[0]) / (2.0 * M_PI)) : 0.0;
  if (closed) theta[n] = theta[0] + 2.0 * M_PI * turns;
  const Series theta_hat = MovingAverage(Derivative(theta, ribbon.h, closed, 2.0 * M_PI * turns), half_rate, closed);
  const Series sigma_hat = MovingAverage(Derivative(sigma, ribbon.h, closed), half_rate, closed);

  ribbon.x.resize(n + 1);
  for (long k = 0; k <= n; ++k)
    ribbon.x[k] = {pos[0][k], pos[1][k], pos[2][k], theta[k], sigma[k], theta_hat[k], sigma_hat[k], width[k], k * ribbon.h};
  SetControlsFromStates(&ribbon);
  return ribbon;
}

}  // namespace ttz::road
