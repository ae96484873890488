#include "lap/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace ttz::lap {
namespace {

TEST(UniformMesh, SpansTheRoadWithEqualIntervalsNoLongerThanDs) {
  const std::vector<double> s = UniformMesh(95.0, 10.0);
  ASSERT_EQ(s.size(), 11u);
  EXPECT_EQ(s.front(), 0.0);
  EXPECT_EQ(s.back(), 95.0);
  for (size_t k = 0; k + 1 < s.size(); ++k) EXPECT_NEAR(s[k + 1] - s[k], 9.5, 1e-12);
}

// A QSS lap accelerating linearly from 4 to 40 m/s over 100 m.
QssLap Ramp() {
  QssLap q;
  q.s = {0.0, 100.0};
  q.V = {4.0, 40.0};
  return q;
}

double SpeedAt(double s) { return 4.0 + 0.36 * s; }

TEST(TimeLimitedMesh, NoIntervalLastsLongerThanDtMaxAndTheUniformNodesStay) {
  const MeshOptions o{10.0, 0.25};
  const std::vector<double> s = TimeLimitedMesh(100.0, Ramp(), o);
  for (size_t k = 0; k + 1 < s.size(); ++k) {
    ASSERT_GT(s[k + 1], s[k]);
    EXPECT_LE(s[k + 1] - s[k], o.ds_m + 1e-12);
    EXPECT_LE((s[k + 1] - s[k]) / SpeedAt(s[k]), o.dt_max_s + 1e-12) << "interval from s = " << s[k];
  }
  for (double u : UniformMesh(100.0, 10.0))
    EXPECT_TRUE(std::any_of(s.begin(), s.end(), [u](double x) { return std::abs(x - u) < 1e-12; })) << u;
  // 0.25 s x 4 m/s = 1 m at the start; above 40 m/s (never here) the 10 m spacing would hold.
  EXPECT_NEAR(s[1], 1.0, 1e-12);
  EXPECT_GT(s.size(), 11u);
}

TEST(TimeLimitedMesh, ADtMaxOfZeroKeepsTheUniformMesh) {
  EXPECT_EQ(TimeLimitedMesh(100.0, Ramp(), MeshOptions{10.0, 0.0}), UniformMesh(100.0, 10.0));
}

}  // namespace
}  // namespace ttz::lap
