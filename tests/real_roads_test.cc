// road_fit on real roads from ../shared/data (acceptance figures of the road_fit issue).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

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

TEST(RealRoads, MountPanorama) {
  const auto road = Fit(kData + "/tracks/mount-panorama-borders-3d.csv", "panorama.h5");
  EXPECT_TRUE(road.closed);
  EXPECT_LT(road.rms_distance_m, 0.25);
  const auto [zmin, zmax] = std::minmax_element(road.z.begin(), road.z.end());
  EXPECT_NEAR(*zmax - *zmin, 175.0, 3.0);
  std::printf("Mount Panorama: length %.1f m, rms %.3f m, elevation range %.1f m\n", road.length_m,
              road.rms_distance_m, *zmax - *zmin);
}

TEST(RealRoads, GeoJsonLineGivesTheSameCourse) {
  const auto road = Fit(kData + "/snaefell/centreline-osm.geojson --width 7 --ds 4", "geojson.h5");
  EXPECT_TRUE(road.closed);
  EXPECT_NEAR(road.length_m / 60641.0, 1.0, 0.003);
}

}  // namespace
