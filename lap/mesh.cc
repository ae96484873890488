#include "lap/mesh.h"

#include <algorithm>
#include <cmath>

namespace ttz::lap {
namespace {

// The QSS speed at s [m/s], linear between its nodes, clamped to its ends.
double QssSpeed(const QssLap& qss, double s) {
  const auto it = std::upper_bound(qss.s.begin(), qss.s.end(), s);
  if (it == qss.s.begin()) return qss.V.front();
  if (it == qss.s.end()) return qss.V.back();
  const size_t k = static_cast<size_t>(it - qss.s.begin());
  const double w = (s - qss.s[k - 1]) / (qss.s[k] - qss.s[k - 1]);
  return (1.0 - w) * qss.V[k - 1] + w * qss.V[k];
}

}  // namespace

std::vector<double> UniformMesh(double length, double ds) {
  const int n = std::max(1, static_cast<int>(std::ceil(length / ds - 1e-9)));
  std::vector<double> s(n + 1);
  for (int i = 0; i <= n; ++i) s[i] = length * i / n;
  return s;
}

std::vector<double> TimeLimitedMesh(double length, const QssLap& qss, const MeshOptions& options) {
  const std::vector<double> uniform = UniformMesh(length, options.ds_m);
  if (options.dt_max_s <= 0.0) return uniform;
  std::vector<double> mesh{uniform.front()};
  for (size_t k = 0; k + 1 < uniform.size(); ++k) {
    const double a = uniform[k], b = uniform[k + 1];
    const double h_max = options.dt_max_s * std::min(QssSpeed(qss, a), QssSpeed(qss, b));
    const int parts = std::max(1, static_cast<int>(std::ceil((b - a) / h_max - 1e-9)));
    for (int i = 1; i <= parts; ++i) mesh.push_back(i == parts ? b : a + (b - a) * i / parts);
  }
  return mesh;
}

std::vector<double> LapMesh(const Vehicle& v, const RoadTrack& road, double length, const MeshOptions& options) {
  const std::vector<double> uniform = UniformMesh(length, options.ds_m);
  if (options.dt_max_s <= 0.0) return uniform;
  return TimeLimitedMesh(length, ComputeQss(v, road, uniform), options);
}

}  // namespace ttz::lap
