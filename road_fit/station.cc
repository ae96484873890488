#include "road_fit/station.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ttz::road {
namespace {

// Nearest point of segment [a, b] to p: fraction t and distance.
Station ProjectOnSegment(const PointXY& a, const PointXY& b, int k, const PointXY& p) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return {k, t, std::hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1])};
}

struct PolylineView {
  const std::vector<PointXY>& v;
  bool closed;
  long segments() const { return static_cast<long>(v.size()) - (closed ? 0 : 1); }
  const PointXY& end(long k) const { return v[(k + 1) % v.size()]; }
};

// Best station over segments first .. first + count - 1 (wrapping on a closed polyline).
Station SearchWindow(const PolylineView& line, long first, long count, const PointXY& p) {
  const long n = line.segments();
  if (!line.closed) {  // an open polyline's window stays inside it
    first = std::clamp(first, 0L, std::max(0L, n - count));
    count = std::min(count, n);
  }
  Station best{0, 0.0, std::numeric_limits<double>::infinity()};
  for (long i = 0; i < count; ++i) {
    long k = first + i;
    if (line.closed) k = ((k % n) + n) % n;
    else if (k < 0 || k >= n) continue;
    const Station s = ProjectOnSegment(line.v[k], line.end(k), static_cast<int>(k), p);
    if (s.distance_m < best.distance_m) best = s;
  }
  return best;
}

}  // namespace

std::vector<Station> ProjectOntoPolyline(const std::vector<PointXY>& vertices, bool closed,
                                         const std::vector<PointXY>& points) {
  constexpr double kLookBackM = 50.0;    // how far behind the previous match a point may lie
  constexpr double kLookAheadM = 100.0;  // slack ahead, beyond three times the point spacing
  constexpr double kLostM = 100.0;       // a match this far off does not move the window
  const PolylineView line{vertices, closed};
  const long n = line.segments();
  std::vector<Station> stations(points.size());
  bool anchored = false;
  long previous = 0;
  double arc_per_segment = 1.0;  // mean segment length, converting metres to segment counts
  if (n > 0) {
    double total = 0.0;
    for (long k = 0; k < n; ++k) total += std::hypot(line.end(k)[0] - vertices[k][0], line.end(k)[1] - vertices[k][1]);
    arc_per_segment = std::max(total / n, 1e-3);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const PointXY& p = points[i];
    if (!anchored) {
      stations[i] = SearchWindow(line, 0, n, p);
    } else {
      const PointXY& q = points[i - 1];
      const double step = std::hypot(p[0] - q[0], p[1] - q[1]);
      const long back = static_cast<long>(std::ceil(kLookBackM / arc_per_segment));
      const long ahead = static_cast<long>(std::ceil((3.0 * step + kLookAheadM) / arc_per_segment));
      stations[i] = SearchWindow(line, previous - back, std::min(n, back + ahead + 1), p);
    }
    if (stations[i].distance_m < kLostM) {
      anchored = true;
      previous = stations[i].interval;
    }
  }
  return stations;
}

std::vector<Station> ProjectOntoRibbon(const Ribbon& ribbon, const std::vector<Observation>& points) {
  // A closed ribbon's last node repeats its first: its polyline is the nodes 0..N-1, closed, so
  // that segment k is still interval k.
  const size_t count = ribbon.x.size() - (ribbon.closed ? 1 : 0);
  std::vector<PointXY> vertices(count), xy(points.size());
  for (size_t k = 0; k < count; ++k) vertices[k] = {ribbon.x[k][kX], ribbon.x[k][kY]};
  for (size_t i = 0; i < points.size(); ++i) xy[i] = {points[i].x_m, points[i].y_m};
  return ProjectOntoPolyline(vertices, ribbon.closed, xy);
}

}  // namespace ttz::road
