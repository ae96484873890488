// Design sensitivities (lap/sensitivity.h) against laps solved again by the indirect solver with
// one bike value 1 % up and 1 % down, on the same mesh, each from its own quasi-steady guess.
#include "lap/sensitivity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
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
  std::string why_not;
  const std::vector<DesignSensitivity> all = DesignSensitivities(bike, road, sol, 2, &why_not);
  ASSERT_EQ(all.size(), SensitivityKeys().size()) << why_not;
  for (const std::string key : {"chassis.base_mass_kg", "aero.drag_area_m2", "drive.gear_ratio",
                                "initial.speed_m_per_s", "motor.current_max_a", "battery.cell_energy_j",
                                "tyre.lateral_adherence", "limits.roll_rate_max_rad_per_s"}) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const DesignSensitivity& d) { return d.key == key; });
    ASSERT_NE(it, all.end()) << key;
    constexpr double kStep = 0.01;
    const double up = Solve(TestBike(key, 1.0 + kStep), road, mesh).lap_time;
    const double down = Solve(TestBike(key, 1.0 - kStep), road, mesh).lap_time;
    const double again = (up - down) / (2.0 * kStep * 100.0);
    EXPECT_NEAR(it->per_percent, again, 0.05 * std::abs(again) + 1e-4) << key;
  }
  // The same figures from one thread as from two.
  const std::vector<DesignSensitivity> one = DesignSensitivities(bike, road, sol, 1, &why_not);
  ASSERT_EQ(one.size(), all.size());
  for (size_t i = 0; i < all.size(); ++i) EXPECT_EQ(one[i].per_unit, all[i].per_unit) << all[i].key;
  // A temperature's 1 % is of its value in kelvin (DesignSensitivity::per_percent).
  const auto ambient = std::find_if(all.begin(), all.end(), [](const DesignSensitivity& d) {
    return d.key == "environment.ambient_temperature_c";
  });
  ASSERT_NE(ambient, all.end());
  EXPECT_DOUBLE_EQ(ambient->per_percent, ambient->per_unit * (ambient->value + 273.15) / 100.0);
  // The lap of another bike is not this one's solution: no sensitivities, and why.
  const std::vector<DesignSensitivity> other = DesignSensitivities(TestBike("chassis.base_mass_kg", 1.1), road, sol,
                                                                   2, &why_not);
  EXPECT_TRUE(other.empty());
  EXPECT_NE(why_not.find("not the solution of its transcription"), std::string::npos) << why_not;
}

// The effort weights (c_y, c_t, c_r: lap/model/cost.h) are left out: their dJ/dp is the
// effort's integral, no lap time.
TEST(SensitivityTest, TheEffortWeightsAreLeftOut) {
  const std::vector<std::string> keys = SensitivityKeys(), real = RealBikeKeys();
  EXPECT_EQ(keys.size() + 3, real.size());
  for (const std::string weight : {"limits.yaw_acceleration_weight_s4_per_rad2",
                                   "limits.torque_rate_weight_s3_per_n2_m2", "limits.roll_rate_weight_s2_per_rad2"}) {
    EXPECT_NE(std::find(real.begin(), real.end(), weight), real.end()) << weight;
    EXPECT_EQ(std::find(keys.begin(), keys.end(), weight), keys.end()) << weight;
  }
}

// Each value's kind (SensitivityKind): the rider's three limits, the six conditions of the day and
// the start, the motor's reference temperature, and the bike's design values, which are the rest;
// every key the lists name is one of SensitivityKeys (a misspelt one would be counted as design).
TEST(SensitivityTest, EachValueHasItsKind) {
  std::map<std::string, int> count;
  for (const std::string& key : SensitivityKeys()) ++count[SensitivityKind(key)];
  EXPECT_EQ(count["rider"], 3);
  EXPECT_EQ(count["condition"], 6);
  EXPECT_EQ(count["reference"], 1);
  EXPECT_EQ(count["design"] + 10, static_cast<int>(SensitivityKeys().size()));
  EXPECT_EQ(count.size(), 4u);
  EXPECT_STREQ(SensitivityKind("environment.gravity_m_per_s2"), "condition");
  EXPECT_STREQ(SensitivityKind("motor.reference_temperature_c"), "reference");
  EXPECT_STREQ(SensitivityKind("limits.roll_rate_max_rad_per_s"), "rider");
  EXPECT_STREQ(SensitivityKind("drive.gear_ratio"), "design");
  EXPECT_STREQ(SensitivityKind("limits.brake_torque_max_n_m"), "design");
}

// An Ipopt lap (eps 0, no barrier costates) has none.
TEST(SensitivityTest, NoneWithoutTheBarriersCostates) {
  const RoadTrack road = TestRoad();
  LapSolution sol;
  sol.s = UniformMesh(road.Length(), 50.0);
  sol.x.assign(sol.s.size(), StateVector<double>{});
  sol.lambda = sol.x;
  sol.u.assign(sol.s.size(), ControlVector<double>{});
  sol.u_interval.assign(sol.s.size() - 1, ControlVector<double>{});
  sol.eps = 1e-4;
  EXPECT_TRUE(HasSensitivities(sol));
  sol.eps = 0.0;
  EXPECT_FALSE(HasSensitivities(sol));
  std::string why_not;
  EXPECT_TRUE(DesignSensitivities(TestBike(), road, sol, 1, &why_not).empty());
  EXPECT_NE(why_not.find("no barrier costates"), std::string::npos) << why_not;
}

}  // namespace
}  // namespace ttz::lap
