// road_fit on real roads from ../shared/data (acceptance figures of the road_fit issue).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/road_artefact.h"

namespace {

namespace fs = std::filesystem;
const std::string kRoadFit = std::string(TTZ_BINARY_DIR) + "/bin/road_fit";
const std::string kData = TTZ_SHARED_DATA;

ttz::RoadArtefact Fit(const std::string& arguments, const std::string& name) {
  const std::string out = (fs::path(::testing::TempDir()) / name).string();
  const int status = std::system((kRoadFit + " " + arguments + " -q -o " + out).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0);
  ttz::RoadArtefact road = ttz::ReadRoad(out);
  fs::remove(out);
  return road;
}

TEST(RealRoads, SnaefellMountainCourse) {
  const auto road = Fit(kData + "/snaefell/centreline-osm.csv --elevation " + kData +
                            "/snaefell/elevation-flightgear.csv --width 7",
                        "snaefell.h5");
  EXPECT_TRUE(road.closed);
  EXPECT_TRUE(road.converged);
  // OSM length by haversine on a sphere: 60,641 m.
  EXPECT_NEAR(road.length_m / 60641.0, 1.0, 0.003);
  EXPECT_LT(road.rms_distance_m, 2.0);
  const auto steepest = std::max_element(road.sigma.begin(), road.sigma.end(),
                                         [](double a, double b) { return std::abs(a) < std::abs(b); }) - road.sigma.begin();
  const auto tightest = std::max_element(road.kappa.begin(), road.kappa.end(),
                                         [](double a, double b) { return std::abs(a) < std::abs(b); }) - road.kappa.begin();
  std::printf("Snaefell: length %.1f m (OSM 60641 m), rms %.3f m, max %.3f m (line %lld); steepest %.1f %% at s = %.0f m "
              "(%.5f, %.5f); tightest radius %.1f m at s = %.0f m (%.5f, %.5f)\n",
              road.length_m, road.rms_distance_m, road.max_distance_m, static_cast<long long>(road.max_distance_line),
              100 * std::tan(road.sigma[steepest]), road.s[steepest], road.centre_lat[steepest],
              road.centre_lon[steepest], 1 / std::abs(road.kappa[tightest]), road.s[tightest],
              road.centre_lat[tightest], road.centre_lon[tightest]);
}

// The cross-slope of each border pair of the file: atan of the elevation difference over the
// horizontal distance, left minus right [rad], in the order of the pairs.
std::vector<double> PanoramaCrossSlopes() {
  std::ifstream in(kData + "/tracks/mount-panorama-borders-3d.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("right_bound_x,right_bound_y,right_bound_z,left_bound_x,left_bound_y,left_bound_z", 0), 0u)
      << line;
  std::vector<double> slopes;
  while (std::getline(in, line)) {
    double v[6];
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) == 6)
      slopes.push_back(std::atan2(v[5] - v[2], std::hypot(v[3] - v[0], v[4] - v[1])));
  }
  return slopes;
}

// 3-D border pairs: the banking is fitted from them, and follows their cross-slopes (up to 9 deg)
// as smoothed; fitted level instead (--level), the ribbon is farther from the points.
TEST(RealRoads, MountPanorama) {
  const auto road = Fit(kData + "/tracks/mount-panorama-borders-3d.csv", "panorama.h5");
  EXPECT_TRUE(road.closed);
  EXPECT_LT(road.rms_distance_m, 0.15);
  const auto [zmin, zmax] = std::minmax_element(road.z.begin(), road.z.end());
  EXPECT_NEAR(*zmax - *zmin, 175.0, 3.0);
  const std::vector<double> slopes = PanoramaCrossSlopes();
  ASSERT_GT(slopes.size(), 6000u);
  // Pair i sits near s = i / pairs * length (about 1 m apart, road.h5 every metre).
  double sum2 = 0.0, data2 = 0.0;
  for (size_t i = 0; i < slopes.size(); ++i) {
    const size_t j = std::min(road.s.size() - 1, static_cast<size_t>(std::lround(i * road.length_m / slopes.size())));
    sum2 += std::pow(road.banking[j] - slopes[i], 2);
    data2 += slopes[i] * slopes[i];
  }
  const double rms = std::sqrt(sum2 / slopes.size()), data_rms = std::sqrt(data2 / slopes.size());
  const auto level = Fit(kData + "/tracks/mount-panorama-borders-3d.csv --level", "panorama_level.h5");
  std::printf("Mount Panorama: length %.1f m, rms %.3f m (level: %.3f m), elevation range %.1f m; banking vs the "
              "pairs' cross-slopes rms %.2f deg (the cross-slopes' own rms %.2f deg)\n",
              road.length_m, road.rms_distance_m, level.rms_distance_m, *zmax - *zmin, rms * 180 / M_PI,
              data_rms * 180 / M_PI);
  EXPECT_LT(rms, 0.5 * data_rms);
  EXPECT_LT(road.rms_distance_m, 0.8 * level.rms_distance_m);
}

// The Las Vegas oval's banking column: 6 to 20 degrees, the outer (right) border the higher.
TEST(RealRoads, LasVegasKeepsItsBanking) {
  const auto road = Fit(kData + "/tracks/las-vegas-centreline-banking.csv", "las_vegas.h5");
  EXPECT_TRUE(road.closed);
  const auto [lo, hi] = std::minmax_element(road.banking.begin(), road.banking.end());
  EXPECT_NEAR(*lo * 180 / M_PI, -20.0, 0.2);
  EXPECT_NEAR(*hi * 180 / M_PI, -6.0, 0.2);
}

TEST(RealRoads, GeoJsonLineGivesTheSameCourse) {
  const auto road = Fit(kData + "/snaefell/centreline-osm.geojson --width 7 --ds 4", "geojson.h5");
  EXPECT_TRUE(road.closed);
  EXPECT_NEAR(road.length_m / 60641.0, 1.0, 0.003);
}

}  // namespace
