// Design sensitivities (lap/sensitivity.h) against laps solved again by the indirect solver with
// one bike value 1 % up and 1 % down, on the same mesh, each from its own quasi-steady guess.
#include "lap/sensitivity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "lap/solver/indirect.h"
#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

// The lap tests' bike (testing::Bx15) as bike.yaml values, `key` scaled by `factor`.
BikeParams TestBike(const std::string& key = "", double factor = 1.0) {
  BikeParams p = LoadBike(std::string(TTZ_SOURCE_DIR) + "/data/bx15.yaml",
                          {testing::kTestVoltageMaxSetting, testing::kTestRollPriceSetting});
  if (!key.empty()) RealBikeValue(p, key) *= factor;
  return p;
}

// 200 m: a 40 m radius left bend from 60 to 130 m, ramped over 10 m, on a 3 % climb.
RoadTrack TestRoad() {
  return RoadTrack(testing::SyntheticRoad(
      200.0, 8.0, [](double s) { return std::clamp(std::min(s - 60.0, 130.0 - s) / 10.0, 0.0, 1.0) / 40.0; },
      [](double) { return std::atan(0.03); }));
}

LapSolution Solve(const BikeParams& p, const RoadTrack& road, const std::vector<double>& mesh) {
  const Vehicle v = MakeVehicle(p);
  const QssLap qss = ComputeQss(v, road, mesh);
  SolveSummary summary;
  const LapSolution sol = SolveIndirect(v, road, mesh, qss.x, {}, qss.u, IndirectOptions{}, &summary);
  EXPECT_TRUE(summary.converged) << summary.message;
  return sol;
}

// Each value 1 % up and down, solved again (a lap with each, on the same 4 m mesh): the adjoint's
// lap time per 1 % agrees within 5 % (+ 1e-4 s per %, the barriers' and the rider's effort's share
// at eps 1e-4). Measured: mass 0.010593 against 0.010607 s per %, drag area 0.0010957 against
// 0.0011311, gear ratio -0.020126 against -0.020718, start speed -0.0090109 against -0.0090306,
// motor current limit -0.020270 against -0.020857, cell energy 0.0063050 against 0.0063131,
// lateral adherence -0.025793 against -0.025413, roll-rate limit -6.5e-5 against -1.4e-4 (within
// the floor: a hundredth of a millisecond a percent).
TEST(SensitivityTest, AgreesWithLapsSolvedAgain) {
  const RoadTrack road = TestRoad();
  const std::vector<double> mesh = UniformMesh(road.Length(), 4.0);
  const BikeParams bike = TestBike();
  const LapSolution sol = Solve(bike, road, mesh);
  ASSERT_TRUE(HasSensitivities(sol));
  const std::vector<DesignSensitivity> all = DesignSensitivities(bike, road, sol, 2);
  ASSERT_EQ(all.size(), RealBikeKeys().size());
  for (const std::string key : {"chassis.base_mass_kg", "aero.drag_area_m2", "drive.gear_ratio",
                                "initial.speed_m_per_s", "motor.current_max_a", "battery.cell_energy_j",
                                "tyre.lateral_adherence", "limits.roll_rate_max_rad_per_s"}) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const DesignSensitivity& d) { return d.key == key; });
    ASSERT_NE(it, all.end()) << key;
    BikeParams same = bike;
    EXPECT_EQ(it->value, RealBikeValue(same, key)) << key;
    EXPECT_NEAR(it->per_percent, it->per_unit * it->value / 100.0, 1e-12 * std::abs(it->per_percent)) << key;
    constexpr double kStep = 0.01;
    const double up = Solve(TestBike(key, 1.0 + kStep), road, mesh).lap_time;
    const double down = Solve(TestBike(key, 1.0 - kStep), road, mesh).lap_time;
    const double again = (up - down) / (2.0 * kStep * 100.0);
    EXPECT_NEAR(it->per_percent, again, 0.05 * std::abs(again) + 1e-4) << key;
  }
}

// An Ipopt lap (eps 0, no barrier costates) has none.
TEST(SensitivityTest, NoneWithoutTheBarriersCostates) {
  const RoadTrack road = TestRoad();
  LapSolution sol;
  sol.s = UniformMesh(road.Length(), 50.0);
  sol.x.assign(sol.s.size(), StateVector<double>{});
  sol.lambda = sol.x;
  sol.u.assign(sol.s.size(), ControlVector<double>{});
  sol.eps = 1e-4;
  EXPECT_TRUE(HasSensitivities(sol));
  sol.eps = 0.0;
  EXPECT_FALSE(HasSensitivities(sol));
  EXPECT_TRUE(DesignSensitivities(TestBike(), road, sol, 1).empty());
}

}  // namespace
}  // namespace ttz::lap
