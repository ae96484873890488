// The QSS lap (lap/qss.h) when the pack cannot last the lap at full power: one pack-power limit
// for the whole lap that leaves 1 % of the pack, instead of full power until the pack is empty.
#include "lap/qss.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "lap/bike.h"
#include "lap/mesh.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

Vehicle Bike(const std::vector<std::string>& overrides = {}) {
  return MakeVehicle(LoadBike(std::string(TTZ_SOURCE_DIR) + "/data/bx15.yaml", overrides));
}

// A 3 km straight level road, on which the full pack spends 4.85 MJ at full power (55.6 s).
class QssPackTest : public ::testing::Test {
 protected:
  RoadTrack road{testing::StraightRoad(3000.0)};
  std::vector<double> mesh = UniformMesh(road.Length(), 10.0);
};

TEST_F(QssPackTest, AFullPackRunsAtFullPower) {
  const Vehicle v = Bike();
  const QssLap q = ComputeQss(v, road, mesh);
  EXPECT_GT(q.x.back()[kE], 0.9 * v.e0);
}

// A pack of 0.96 MJ (96 cells of 10 kJ, as heavy as the full pack: only the energy differs) ends
// the lap with between 1 % (the reserve) and 1.5 % of its energy (the bisection stops at 0.1 % of
// the power limit), and so spends the rest of it over the whole lap; full power until the pack is
// empty would end it at 0. (Measured: 124.2 s, 12.8 kJ left.)
TEST_F(QssPackTest, ASmallPackSpreadsItsEnergyOverTheLap) {
  const Vehicle full = Bike();
  const Vehicle small = Bike({"battery.cell_energy_j=10000", "battery.energy_density_j_per_kg=9600"});
  ASSERT_DOUBLE_EQ(small.M, full.M);
  const QssLap q_full = ComputeQss(full, road, mesh);
  const QssLap q = ComputeQss(small, road, mesh);
  const double used_full = full.e0 - q_full.x.back()[kE];
  ASSERT_GT(used_full, 1.5 * small.e0);
  EXPECT_GE(q.x.back()[kE], 0.01 * small.e0);
  EXPECT_LE(q.x.back()[kE], 0.015 * small.e0);
  EXPECT_GT(q.lap_time, q_full.lap_time);
  for (const StateVector<double>& x : q.x) EXPECT_GT(x[kE], 0.0);
  std::cout << "QSS on 3 km: full pack " << q_full.lap_time << " s using " << used_full
            << " J; a " << small.e0 << " J pack " << q.lap_time << " s, " << q.x.back()[kE]
            << " J left\n";
}

}  // namespace
}  // namespace ttz::lap
