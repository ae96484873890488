// road_fit on bad input: one clear line on stderr naming the file and line or column, exit code 2,
// and neither road.h5 nor a temporary file left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/road_artefact.h"

namespace {

namespace fs = std::filesystem;
const std::string kRoadFit = std::string(TTZ_BINARY_DIR) + "/bin/road_fit";

struct CliRun {
  int exit_code;
  std::string stderr_text;
};

class RoadFitCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("road_fit_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string File(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::string Output() const { return (dir_ / "road.h5").string(); }

  CliRun RoadFit(const std::string& arguments) const {
    const std::string err = (dir_ / "stderr.txt").string();
    const int status = std::system((kRoadFit + " " + arguments + " -o " + Output() + " > /dev/null 2> " + err).c_str());
    std::ifstream in(err);
    std::stringstream text;
    text << in.rdbuf();
    fs::remove(err);
    return {WEXITSTATUS(status), text.str()};
  }

  // A gentle 400 m curve, left and right borders 7 m apart, one point every 10 m per side.
  static std::string BorderRows(int points_per_side, int skip_side = -1) {
    std::ostringstream rows;
    rows.precision(10);
    for (int side = 0; side < 2; ++side) {
      if (side == skip_side) continue;
      for (int i = 0; i < points_per_side; ++i) {
        const double s = 10.0 * i, theta = s / 300.0, offset = side == 0 ? 3.5 : -3.5;
        const double x = 300.0 * std::sin(theta) - offset * std::sin(theta);
        const double y = 300.0 * (1 - std::cos(theta)) + offset * std::cos(theta);
        rows << (side == 0 ? "left," : "right,") << 54.2 + y / 111200.0 << "," << -4.5 + x / 65300.0 << ","
             << 100 + 0.03 * s << "\n";
      }
    }
    return rows.str();
  }

  void ExpectBadInput(const CliRun& run, const std::string& must_contain) const {
    EXPECT_EQ(run.exit_code, 2) << run.stderr_text;
    EXPECT_EQ(std::count(run.stderr_text.begin(), run.stderr_text.end(), '\n'), 1) << run.stderr_text;
    EXPECT_NE(run.stderr_text.find(must_contain), std::string::npos)
        << "stderr: " << run.stderr_text << "expected to contain: " << must_contain;
    EXPECT_FALSE(fs::exists(Output()));
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }

  fs::path dir_;
};

TEST_F(RoadFitCli, AGoodInputFitsAndWritesTheArtefact) {
  const CliRun run = RoadFit(File("good.csv", "side,lat,lon,elevation\n" + BorderRows(40)));
  EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
  EXPECT_TRUE(fs::exists(Output()));
}

TEST_F(RoadFitCli, MissingFile) { ExpectBadInput(RoadFit((dir_ / "none.csv").string()), "none.csv: file not found"); }

TEST_F(RoadFitCli, EmptyFile) {
  const auto f = File("empty.csv", "");
  ExpectBadInput(RoadFit(f), f + ": empty file");
}

TEST_F(RoadFitCli, NoHeader) {
  const auto f = File("noheader.csv", "1,54.2,-4.5\n2,54.3,-4.6\n");
  ExpectBadInput(RoadFit(f), f + ":1: no header");
}

TEST_F(RoadFitCli, UnknownColumns) {
  const auto f = File("columns.csv", "a,b,c\n1,2,3\n");
  ExpectBadInput(RoadFit(f), f + ": unknown columns (a,b,c)");
}

TEST_F(RoadFitCli, NonNumericCell) {
  const auto f = File("text.csv", "side,lat,lon,elevation\n" + BorderRows(40) + "left,54.2,abc,10\n");
  ExpectBadInput(RoadFit(f), f + ":82: column 'lon': 'abc' is not a number");
}

TEST_F(RoadFitCli, NaNAndInfinity) {
  const auto f = File("nan.csv", "side,lat,lon,elevation\nleft,nan,-4.5,10\n" + BorderRows(40));
  ExpectBadInput(RoadFit(f), f + ":2: column 'lat': 'nan' is not finite");
  const auto g = File("inf.csv", "side,lat,lon,elevation\nleft,54.2,-4.5,inf\n" + BorderRows(40));
  ExpectBadInput(RoadFit(g), g + ":2: column 'elevation': 'inf' is not finite");
}

TEST_F(RoadFitCli, LatitudeAndLongitudeOutOfRange) {
  const auto f = File("lat.csv", "side,lat,lon,elevation\nleft,94.2,-4.5,10\n" + BorderRows(40));
  ExpectBadInput(RoadFit(f), f + ":2: latitude 94.2");
  const auto g = File("lon.csv", "side,lat,lon,elevation\nleft,54.2,-184.5,10\n" + BorderRows(40));
  ExpectBadInput(RoadFit(g), g + ":2: longitude -184.5");
}

TEST_F(RoadFitCli, FewerThanTenPoints) {
  const auto f = File("few.csv", "side,lat,lon,elevation\n" + BorderRows(9));
  ExpectBadInput(RoadFit(f), f + ": 9 left points, at least 10 expected");
}

TEST_F(RoadFitCli, OnlyOneSide) {
  const auto f = File("oneside.csv", "side,lat,lon,elevation\n" + BorderRows(40, 1));
  ExpectBadInput(RoadFit(f), f + ": no right border points");
}

TEST_F(RoadFitCli, UnknownSide) {
  const auto f = File("side.csv", "side,lat,lon,elevation\nmiddle,54.2,-4.5,10\n" + BorderRows(40));
  ExpectBadInput(RoadFit(f), f + ":2: column 'side': side 'middle' is not left or right");
}

TEST_F(RoadFitCli, DuplicateConsecutivePointsAreToleratedWithAWarning) {
  std::string rows = BorderRows(40);
  const std::string first = rows.substr(0, rows.find('\n') + 1);
  const CliRun run = RoadFit(File("dup.csv", "side,lat,lon,elevation\n" + first + rows));
  EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
  EXPECT_NE(run.stderr_text.find("duplicate consecutive point"), std::string::npos) << run.stderr_text;
  EXPECT_TRUE(fs::exists(Output()));
}

// A banked centre line in local metres (as ../shared/data/tracks/las-vegas-centreline-banking.csv):
// a 400 m left arc of 300 m radius, banked 0.15 rad with its outer (right) border the higher.
// road.h5 carries the banking, in radians or from degrees, and the in-plane curvature it tilts;
// a centre line without the column, or fitted with --level, is level; a banking without a unit,
// or beyond 45 degrees, is refused in one line.
TEST_F(RoadFitCli, ABankedCentreLineKeepsItsBanking) {
  const auto rows = [](const std::string& banking) {
    std::ostringstream text;
    for (int i = 0; i < 40; ++i) {
      const double theta = 10.0 * i / 300.0;
      text << 300.0 * std::sin(theta) << "," << 300.0 * (1 - std::cos(theta)) << ",6,6" << banking << "\n";
    }
    return text.str();
  };
  const auto middle = [&] {
    const ttz::RoadArtefact road = ttz::ReadRoad(Output());
    return road.s.size() / 2;
  };
  const CliRun rad = RoadFit(File("banked.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m,banking_rad\n" + rows(",-0.15")));
  ASSERT_EQ(rad.exit_code, 0) << rad.stderr_text;
  EXPECT_EQ(rad.stderr_text.find("banking"), std::string::npos) << rad.stderr_text;
  {
    const ttz::RoadArtefact road = ttz::ReadRoad(Output());
    const size_t i = middle();
    EXPECT_NEAR(road.banking[i], -0.15, 1e-3);
    EXPECT_NEAR(road.kappa[i], std::cos(0.15) / 300.0, 2e-5);  // the turn, tilted into the banked plane
    EXPECT_NEAR(road.nu[i], std::sin(0.15) / 300.0, 2e-5);     // and out of it: pressing the bike down
  }
  ASSERT_EQ(RoadFit(File("deg.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m,bank_deg\n" + rows(",-8.594"))).exit_code, 0);
  EXPECT_NEAR(ttz::ReadRoad(Output()).banking[middle()], -0.15, 1e-3);
  const CliRun level = RoadFit(File("level.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m\n" + rows("")));
  ASSERT_EQ(level.exit_code, 0) << level.stderr_text;
  for (double xi : ttz::ReadRoad(Output()).banking) ASSERT_EQ(xi, 0.0);
  ASSERT_EQ(RoadFit(File("banked.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m,banking_rad\n" + rows(",-0.15")) +
                    " --level").exit_code, 0);
  const ttz::RoadArtefact held = ttz::ReadRoad(Output());
  for (double xi : held.banking) ASSERT_EQ(xi, 0.0);
  EXPECT_NEAR(held.kappa[middle()], 1.0 / 300.0, 2e-5);  // the level turn again
  fs::remove(Output());
  const auto bare = File("bare.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m,banking\n" + rows(",-0.15"));
  ExpectBadInput(RoadFit(bare), bare + ": column 'banking': banking without a unit: name it banking_rad or banking_deg");
  const auto steep = File("steep.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m,banking_deg\n" + rows(",50"));
  ExpectBadInput(RoadFit(steep), steep + ":2: column 'banking_deg': banking 50 is not within +-45 deg");
  // a file that is no form at all: its error alone
  const auto bad = File("bad.csv", "bank_rad,foo\n1,2\n");
  ExpectBadInput(RoadFit(bad), bad + ": unknown columns (bank_rad,foo)");
}

TEST_F(RoadFitCli, AFarOutlierIsAnErrorOrAbsorbedWithRobust) {
  std::string rows = BorderRows(40);
  // Line 22 (the 21st left point) moved 10 km north.
  size_t at = 0;
  for (int i = 0; i < 20; ++i) at = rows.find('\n', at) + 1;
  const size_t end = rows.find('\n', at);
  std::string row = rows.substr(at, end - at);
  const size_t c1 = row.find(','), c2 = row.find(',', c1 + 1);
  const double lat = std::stod(row.substr(c1 + 1, c2 - c1 - 1)) + 10000.0 / 111200.0;
  rows.replace(at, end - at, "left," + std::to_string(lat) + row.substr(c2));
  const auto f = File("outlier.csv", "side,lat,lon,elevation\n" + rows);
  ExpectBadInput(RoadFit(f), f + ":22: point");
  const CliRun robust = RoadFit(f + " --robust");
  EXPECT_EQ(robust.exit_code, 0) << robust.stderr_text;
  EXPECT_TRUE(fs::exists(Output()));
}

TEST_F(RoadFitCli, UnreadableRaster) {
  const auto centre = File("centre.csv", [] {
    std::string t = "lat,lon\n";
    for (int i = 0; i < 20; ++i) t += std::to_string(54.2 + i * 1e-4) + ",-4.5\n";
    return t;
  }());
  const auto raster = File("dem.tif", "not a raster");
  ExpectBadInput(RoadFit(centre + " --width 7 --elevation " + raster), raster + ": cannot be read as a raster");
}

TEST_F(RoadFitCli, CentreLineWithoutWidth) {
  const auto centre = File("centre.csv", [] {
    std::string t = "lat,lon\n";
    for (int i = 0; i < 20; ++i) t += std::to_string(54.2 + i * 1e-4) + ",-4.5\n";
    return t;
  }());
  ExpectBadInput(RoadFit(centre), centre + ": no width column");
}

TEST_F(RoadFitCli, UnwritableOutputPath) {
  const auto f = File("good.csv", "side,lat,lon,elevation\n" + BorderRows(40));
  const std::string err = (dir_ / "stderr.txt").string();
  const int status = std::system((kRoadFit + " " + f + " -o /nonexistent-dir/road.h5 > /dev/null 2> " + err).c_str());
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(WEXITSTATUS(status), 2);
  // Checked before the input is read and fitted (session 53; it had been found only at the end).
  EXPECT_NE(text.str().find("/nonexistent-dir/road.h5: cannot be written (the folder /nonexistent-dir does not exist)"),
            std::string::npos)
      << text.str();
}

// A road whose ends are 363 m apart (390 m of a 300 m radius bend) is not a circuit: --closed would
// bridge the gap with a made-up straight.
TEST_F(RoadFitCli, ClosingARoadWhoseEndsAreFarApart) {
  const auto f = File("arc.csv", "side,lat,lon,elevation\n" + BorderRows(40));
  ExpectBadInput(RoadFit(f + " --closed"), f + ": the road's ends are 363 m apart, too far for --closed");
}

TEST_F(RoadFitCli, BadOption) { ExpectBadInput(RoadFit("x.csv --ds -1"), "--ds"); }

}  // namespace
