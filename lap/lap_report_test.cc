// Tests of lap/lap_report.h: the m:ss.s lap time, the text summary and the JSON object.
#include "lap/lap_report.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ttz::lap {
namespace {

TEST(LapReportTest, LapTimeAsMinutesSecondsAndTenths) {
  EXPECT_EQ(FormatLapTime(10.946), "0:10.9");
  EXPECT_EQ(FormatLapTime(72.46), "1:12.5");
  EXPECT_EQ(FormatLapTime(59.96), "1:00.0");  // rounds into the next minute
  EXPECT_EQ(FormatLapTime(1127.0), "18:47.0");
  EXPECT_EQ(FormatLapTime(NAN), "-:--.-");
}

class LapReportFigures : public ::testing::Test {
 protected:
  void SetUp() override {
    sol.s = {0.0, 100.0, 200.0};
    sol.lap_time_extrapolated = 10.0;
    f.lap_time = 10.04;
    f.average_speed = 20.0;
    f.energy_used = 5.1e5;
    f.energy_fraction = 0.01;
    f.top_speed = 25.0;
    f.start_speed = 5.0;
    resim.passed = true;
    resim.lap_time = 10.039;
    resim.lap_time_difference = -0.001;
    resim.lap_time_relative = 1e-4;
    resim.max_state_difference_all = 2.5e-4;
    resim.worst_state = kV;
    resim.worst_s = 123.4;
  }
  LapSolution sol;
  SolveSummary summary;
  LapFigures f;
  ResimReport resim;
};

TEST_F(LapReportFigures, TextInHumanUnits) {
  summary.converged = true;
  const std::string text = LapReportText(sol, summary, f, resim, {});
  EXPECT_NE(text.find("0:10.0"), std::string::npos) << text;
  EXPECT_NE(text.find("72.0 km/h"), std::string::npos) << text;
  EXPECT_NE(text.find("0.51 MJ (1.0 % of the pack)"), std::string::npos) << text;
  EXPECT_NE(text.find("top speed      90.0 km/h\nstart speed    18.0 km/h\n"), std::string::npos) << text;
  EXPECT_NE(text.find("re-simulation  lap time differs by 0.01 %, states by 0.025 % (V at s = 123 m)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("converged      yes"), std::string::npos) << text;
  EXPECT_EQ(text.find("NOT CONVERGED"), std::string::npos) << text;
}

TEST_F(LapReportFigures, TextSaysWhenTheReSimulationFailedOrDiverged) {
  resim.passed = false;
  EXPECT_NE(LapReportText(sol, summary, f, resim, {}).find("states by 0.025 % (V at s = 123 m; failed)\n"), std::string::npos);
  resim.lap_time = NAN;
  resim.message = "re-simulation diverged: phi off by 120 % of its scale at s = 30 m";
  EXPECT_NE(LapReportText(sol, summary, f, resim, {}).find("re-simulation  no lap time (" + resim.message + ")\n"),
            std::string::npos);
}

TEST_F(LapReportFigures, TextSaysWhyNotConverged) {
  summary.message = "residual 0.1; ";
  const std::string text = LapReportText(sol, summary, f, resim, {});
  EXPECT_EQ(text.find("NOT CONVERGED: the figures below are of the solver's last point"), 0u) << text;
  EXPECT_NE(text.find("converged      no (residual 0.1)"), std::string::npos) << text;
  EXPECT_EQ(SolveMessage(summary), "residual 0.1");
}

TEST_F(LapReportFigures, JsonInSiUnitsWithNullForNonFinite) {
  summary.max_residual = HUGE_VAL;
  summary.message = "say \"why\"";
  const std::string json = LapReportJson(sol, summary, f, resim, {});
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.substr(json.size() - 2), "}\n");
  EXPECT_NE(json.find("\"lap_time\": 10.04,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"start_speed\": 5,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"max_residual\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"message\": \"say \\\"why\\\"\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"converged\": false"), std::string::npos) << json;
  EXPECT_NE(json.find("\"resim_lap_time_relative\": 0.0001,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"resim_passed\": true"), std::string::npos) << json;
  EXPECT_NE(json.find("\"resim_worst_state\": \"V\", \"resim_worst_s\": 123.4,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"nodes\": 3, \"sensitivity_per_percent\": {}, \"sensitivity_kind\": {}}"), std::string::npos)
      << json;
}

// The text names the kReportedSensitivities largest of the design values by size, largest first;
// the JSON has them all, with their kinds.
TEST_F(LapReportFigures, TheLargestSensitivitiesFirstAndAllInJson) {
  std::vector<DesignSensitivity> all;
  for (int i = 0; i < kReportedSensitivities + 2; ++i)  // sizes 0, -0.1, 0.2, -0.3, ...
    all.push_back({"section.key" + std::to_string(i), "design", 1.0, 0.0, (i % 2 ? -0.1 : 0.1) * i});
  all.push_back({"section.nan", "design", 1.0, NAN, NAN});  // not ranked, null in JSON
  all.push_back({"section.gravity", "condition", 1.0, 0.0, -9.0});  // the largest, but no design value
  const std::string text = LapReportText(sol, summary, f, resim, all);
  EXPECT_EQ(text.find("section.nan"), std::string::npos) << text;
  EXPECT_EQ(text.find("section.gravity"), std::string::npos) << text;
  const size_t largest = text.find("section.key6"), next = text.find("section.key5");
  ASSERT_NE(largest, std::string::npos) << text;
  EXPECT_LT(largest, next) << text;
  EXPECT_NE(text.find("+0.600 s"), std::string::npos) << text;
  EXPECT_NE(text.find("-0.500 s"), std::string::npos) << text;
  EXPECT_EQ(text.find("section.key1 "), std::string::npos) << text;  // the two smallest are left out
  EXPECT_EQ(text.find("section.key0 "), std::string::npos) << text;
  const std::string json = LapReportJson(sol, summary, f, resim, all);
  EXPECT_NE(json.find("\"sensitivity_per_percent\": {\"section.key0\": 0, \"section.key1\": -0.1,"),
            std::string::npos) << json;
  EXPECT_NE(json.find("\"section.nan\": null, \"section.gravity\": -9}"), std::string::npos) << json;
  EXPECT_NE(json.find("\"sensitivity_kind\": {\"section.key0\": \"design\","), std::string::npos) << json;
  EXPECT_NE(json.find("\"section.gravity\": \"condition\"}}"), std::string::npos) << json;
}

}  // namespace
}  // namespace ttz::lap
