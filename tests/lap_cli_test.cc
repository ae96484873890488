// The `lap` command on synthetic roads the test writes itself: a straight level road solves and
// gives a complete lap.h5 and summary, and warm-starts a second solve; every bad input gives exit
// code 2, one line on stderr naming the file or key, and no lap.h5 (nor a temporary file).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "common/artefact.h"
#include "common/road_artefact.h"
#include "lap/sensitivity.h"
#include "lap/model/constraints.h"
#include "lap/solver/indirect.h"
#include "lap/solver/ipopt_direct.h"
#include "lap/testing/test_bike.h"

namespace {

namespace fs = std::filesystem;
const std::string kLap = std::string(TTZ_BINARY_DIR) + "/bin/lap";
const std::string kBike = std::string(TTZ_SOURCE_DIR) + "/data/bx15.yaml";

struct CliRun {
  int exit_code;
  std::string stdout_text, stderr_text;
};

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Makes the artefact at `path` look as an older version wrote it: without the group or dataset
// `added` that `version` did not have, and with that schema_version.
void AsAnOlderVersion(const std::string& path, const char* added, int64_t version) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_GE(H5Ldelete(file, added, H5P_DEFAULT), 0);
  const hid_t attribute = H5Aopen(file, "schema_version", H5P_DEFAULT);
  EXPECT_GE(H5Awrite(attribute, H5T_NATIVE_INT64, &version), 0);
  H5Aclose(attribute);
  H5Fclose(file);
}

// A straight level road of `length` metres sampled every metre, `width(s)` wide.
ttz::RoadArtefact StraightRoad(double length, double (*width)(double) = [](double) { return 8.0; }) {
  ttz::RoadArtefact r;
  for (int i = 0; i <= static_cast<int>(length); ++i) {
    const double s = i, w = width(s);
    r.s.push_back(s);
    r.x.push_back(s);
    r.left_x.push_back(s);
    r.right_x.push_back(s);
    r.left_y.push_back(0.5 * w);
    r.right_y.push_back(-0.5 * w);
    r.width.push_back(w);
    for (auto* f : {&r.y, &r.z, &r.theta, &r.sigma, &r.banking, &r.kappa, &r.nu, &r.tau}) f->push_back(0.0);
  }
  r.length_m = length;
  r.ds_m = 1.0;
  r.input_format = "synthetic";
  r.tool_version = "test";
  r.converged = true;
  return r;
}

// A level closed road 8 m wide, sampled every metre, as road_fit writes a circuit (closed = 1):
// a stadium of two `straight`-metre straights joined by half circles of `radius` metres turning
// left, starting halfway along a straight. Heading and position by the midpoint rule along s.
ttz::RoadArtefact StadiumRoad(double straight, double radius) {
  const double arc = M_PI * radius, length = 2.0 * (straight + arc);
  const auto kappa = [&](double s) {
    const double along = std::fmod(s + 0.5 * straight, straight + arc);  // from a straight's start
    return along > straight ? 1.0 / radius : 0.0;
  };
  ttz::RoadArtefact r;
  const int n = static_cast<int>(length);
  const double h = length / n;
  double theta = 0.0, x = 0.0, y = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double s = i * h;
    if (i > 0) {
      const double mid = theta + 0.5 * h * kappa(s - 0.5 * h);
      x += h * std::cos(mid);
      y += h * std::sin(mid);
      theta += h * kappa(s - 0.5 * h);
    }
    r.s.push_back(s);
    r.x.push_back(x);
    r.y.push_back(y);
    r.theta.push_back(theta);
    r.kappa.push_back(kappa(s));
    r.width.push_back(8.0);
    r.left_x.push_back(x - 4.0 * std::sin(theta));
    r.left_y.push_back(y + 4.0 * std::cos(theta));
    r.right_x.push_back(x + 4.0 * std::sin(theta));
    r.right_y.push_back(y - 4.0 * std::cos(theta));
    for (auto* f : {&r.z, &r.sigma, &r.banking, &r.nu, &r.tau}) f->push_back(0.0);
  }
  r.length_m = length;
  r.ds_m = h;
  r.closed = true;
  r.input_format = "synthetic";
  r.tool_version = "test";
  r.converged = true;
  return r;
}

// Every dataset of an HDF5 file, by name, with whether it has a `units` attribute.
std::vector<std::pair<std::string, bool>> DatasetsAndUnits(const std::string& path) {
  std::vector<std::pair<std::string, bool>> found;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(file, 0) << path;
  auto visit = [](hid_t object, const char* name, const H5O_info_t* info, void* out) -> herr_t {
    if (info->type == H5O_TYPE_DATASET)
      static_cast<std::vector<std::pair<std::string, bool>>*>(out)->emplace_back(
          name, H5Aexists_by_name(object, name, "units", H5P_DEFAULT) > 0);
    return 0;
  };
  H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, visit, &found, H5O_INFO_BASIC);
  H5Fclose(file);
  return found;
}

class LapCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("lap_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  std::string File(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
    return Path(name);
  }
  std::string Road(const std::string& name, const ttz::RoadArtefact& road) const {
    ttz::WriteRoad(Path(name), road);
    return Path(name);
  }
  // bx15.yaml with `line` replaced by `replacement` (the line must exist).
  std::string Bike(const std::string& line, const std::string& replacement) const {
    std::string text = ReadText(kBike);
    const size_t at = text.find(line);
    EXPECT_NE(at, std::string::npos) << line;
    return File("bike.yaml", text.replace(at, line.size(), replacement));
  }

  CliRun Lap(const std::string& arguments, const std::string& output = "lap.h5") const {
    const std::string out = Path("stdout.txt"), err = Path("stderr.txt");
    const int status = std::system((kLap + " " + arguments + " -o " + Path(output) + " > " + out + " 2> " + err).c_str());
    CliRun run{WEXITSTATUS(status), ReadText(out), ReadText(err)};
    fs::remove(out);
    fs::remove(err);
    return run;
  }

  void ExpectBadInput(const CliRun& run, const std::string& must_contain, const std::string& output = "lap.h5") const {
    EXPECT_EQ(run.exit_code, 2) << run.stderr_text;
    EXPECT_EQ(std::count(run.stderr_text.begin(), run.stderr_text.end(), '\n'), 1) << run.stderr_text;
    EXPECT_NE(run.stderr_text.find(must_contain), std::string::npos)
        << "stderr: " << run.stderr_text << "expected to contain: " << must_contain;
    EXPECT_FALSE(fs::exists(Path(output)));
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }

  fs::path dir_;
};

TEST_F(LapCli, AStraightRoadSolvesWritesLapH5AndWarmStartsTheNextSolve) {
  const std::string road = Road("straight200.h5", StraightRoad(200.0));
  const CliRun run = Lap(road + " " + kBike + " --ds 2 -q");
  ASSERT_EQ(run.exit_code, 0) << run.stderr_text << run.stdout_text;
  EXPECT_TRUE(std::regex_search(run.stdout_text, std::regex("lap time +0:[01][0-9]\\.[0-9] ")))
      << run.stdout_text;
  EXPECT_NE(run.stdout_text.find("re-simulation  lap time differs by "), std::string::npos) << run.stdout_text;
  EXPECT_NE(run.stdout_text.find("converged      yes"), std::string::npos) << run.stdout_text;
  EXPECT_NE(run.stdout_text.find("sensitivity    lap time per 1 % more of (the largest design values"), std::string::npos)
      << run.stdout_text;

  const std::string lap = Path("lap.h5");
  const ttz::ArtefactReader r(lap, "ttz.lap", 4);
  EXPECT_TRUE(r.ReadBoolAttribute("converged"));
  // Design sensitivities (lap/sensitivity.h): one row per real bike.yaml key; on a level straight
  // from a standing start more mass costs time, a larger motor-current limit buys some.
  const std::vector<double> per_percent = r.ReadVector("sensitivity/per_percent", "s");
  const std::vector<std::string> keys = ttz::lap::SensitivityKeys();
  ASSERT_EQ(per_percent.size(), keys.size());
  EXPECT_EQ(r.ReadStringVector("sensitivity/key"), keys);
  const std::vector<std::string> kinds = r.ReadStringVector("sensitivity/kind");
  ASSERT_EQ(kinds.size(), keys.size());
  for (size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(kinds[i], ttz::lap::SensitivityKind(keys[i])) << keys[i];
  const auto of = [&](const std::string& key) {
    return per_percent[std::find(keys.begin(), keys.end(), key) - keys.begin()];
  };
  EXPECT_GT(of("chassis.base_mass_kg"), 0.0);
  EXPECT_LT(of("motor.current_max_a"), 0.0);
  EXPECT_EQ(r.ReadStringAttribute("road_sha256"), ttz::FileSha256(road));
  EXPECT_EQ(r.ReadStringAttribute("guess"), "racing-line");  // the default
  EXPECT_GT(r.ReadDoubleAttribute("guess_lap_time"), r.ReadDoubleAttribute("lap_time"));
  // 101 nodes 2 m apart, and the launch's intervals split to 0.25 s of the QSS speed (lap/mesh.h)
  const size_t nodes = r.ReadIntAttribute("nodes");
  EXPECT_GT(nodes, 101u);
  EXPECT_LT(nodes, 110u);
  const std::vector<double> t = r.ReadVector("t", "s");
  ASSERT_EQ(t.size(), nodes);
  EXPECT_EQ(t.front(), 0.0);
  for (size_t k = 1; k < t.size(); ++k) EXPECT_GT(t[k], t[k - 1]) << "node " << k;
  EXPECT_NEAR(r.ReadDoubleAttribute("lap_time"), t.back(), 1e-12);
  EXPECT_EQ(r.ReadVector("state/V", "m/s").size(), nodes);
  EXPECT_EQ(r.ReadVector("qss/V", "m/s").size(), nodes);
  const auto datasets = DatasetsAndUnits(lap);
  EXPECT_GT(datasets.size(), 60u);
  for (const auto& [name, has_units] : datasets) EXPECT_TRUE(has_units) << name;

  // Warm start on a coarser mesh of the same road, summary as JSON.
  const CliRun warm = Lap(road + " " + kBike + " --ds 4 -q --json --init " + lap, "warm.h5");
  ASSERT_EQ(warm.exit_code, 0) << warm.stderr_text << warm.stdout_text;
  EXPECT_EQ(warm.stdout_text.front(), '{') << warm.stdout_text;
  EXPECT_EQ(std::count(warm.stdout_text.begin(), warm.stdout_text.end(), '\n'), 1) << warm.stdout_text;
  EXPECT_NE(warm.stdout_text.find("\"lap_time\": "), std::string::npos) << warm.stdout_text;
  EXPECT_NE(warm.stdout_text.find("\"converged\": true"), std::string::npos) << warm.stdout_text;
  const ttz::ArtefactReader w(Path("warm.h5"), "ttz.lap", 4);
  EXPECT_EQ(w.ReadStringAttribute("init_file"), lap);
  EXPECT_FALSE(w.ReadBoolAttribute("mesh_from_init"));  // --ds 4, not 2
  EXPECT_EQ(w.ReadStringAttribute("guess"), "init");
  EXPECT_NEAR(w.ReadDoubleAttribute("lap_time"), r.ReadDoubleAttribute("lap_time"), 0.01 * t.back());

  // The same lap as the warm start of another (longer) road is refused.
  const std::string other = Road("straight300.h5", StraightRoad(300.0));
  ExpectBadInput(Lap(other + " " + kBike + " --ds 4 --init " + lap, "other.h5"),
                 lap + ": is a lap of another road", "other.h5");
}

// The oracle's answer warm-starts the indirect solver (both use the midpoint rule on the same mesh).
TEST_F(LapCli, TheIpoptOracleSolvesAndWarmStartsTheIndirectSolver) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const CliRun ipopt = Lap(road + " " + kBike + " --ds 1 -q --solver ipopt", "ipopt.h5");
  ASSERT_EQ(ipopt.exit_code, 0) << ipopt.stderr_text << ipopt.stdout_text;
  const ttz::ArtefactReader r(Path("ipopt.h5"), "ttz.lap", 4);
  EXPECT_EQ(r.ReadStringAttribute("solver"), "ipopt");
  EXPECT_EQ(r.ReadDoubleAttribute("eps"), 0.0);
  EXPECT_TRUE(r.ReadBoolAttribute("converged"));
  EXPECT_FALSE(r.HasDataset("sensitivity/per_percent"));  // no barrier costates (lap/sensitivity.h)
  EXPECT_TRUE(r.ReadBoolAttribute("resim_passed"));
  // Ipopt checks the nodes too: what the solver checked and what the nodes report both hold.
  for (const char* kind : ttz::lap::kConstraintNames) {
    EXPECT_LE(r.ReadDoubleAttribute(std::string("solver_max_violation_") + kind), 1e-4) << kind;
    EXPECT_LE(r.ReadDoubleAttribute(std::string("max_violation_") + kind), 1e-4) << kind;
  }
  EXPECT_LT(r.ReadDoubleAttribute("resim_lap_time_relative"), 1e-3);
  EXPECT_NEAR(r.ReadDoubleAttribute("resim_lap_time"),
              r.ReadDoubleAttribute("lap_time") + r.ReadDoubleAttribute("resim_lap_time_difference"), 1e-9);

  const CliRun warm = Lap(road + " " + kBike + " --ds 1 -q --init " + Path("ipopt.h5"), "warm.h5");
  ASSERT_EQ(warm.exit_code, 0) << warm.stderr_text << warm.stdout_text;
  const ttz::ArtefactReader w(Path("warm.h5"), "ttz.lap", 4);
  EXPECT_EQ(w.ReadStringAttribute("solver"), "indirect");
  EXPECT_NEAR(w.ReadDoubleAttribute("lap_time_extrapolated"), r.ReadDoubleAttribute("lap_time"),
              1e-3 * r.ReadDoubleAttribute("lap_time"));
}

// --start flying on a closed stadium (straights of 150 m, bends of 30 m radius): the bike crosses
// the line, halfway along a straight, at the speed with which the QSS lap on the centre line
// arrives back there (recorded as initial.speed_m_per_s in bike_yaml, and start = flying), where
// the standing start is at 5 m/s, and the lap is the faster. On an open road it is refused.
TEST_F(LapCli, AFlyingStartOnAClosedRoad) {
  const std::string stadium = Road("stadium.h5", StadiumRoad(150.0, 30.0));
  const CliRun standing = Lap(stadium + " " + kBike + " --ds 5 -q", "standing.h5");
  const CliRun flying = Lap(stadium + " " + kBike + " --ds 5 -q --start flying", "flying.h5");
  ASSERT_TRUE(standing.exit_code == 0 || standing.exit_code == 4) << standing.exit_code << standing.stderr_text;
  ASSERT_TRUE(flying.exit_code == 0 || flying.exit_code == 4) << flying.exit_code << flying.stderr_text;
  const ttz::ArtefactReader s(Path("standing.h5"), "ttz.lap", 4), f(Path("flying.h5"), "ttz.lap", 4);
  EXPECT_TRUE(f.ReadBoolAttribute("converged"));
  EXPECT_EQ(s.ReadStringAttribute("start"), "standing");
  EXPECT_EQ(f.ReadStringAttribute("start"), "flying");
  const double V0 = f.ReadVector("state/V", "m/s").front();
  EXPECT_EQ(s.ReadVector("state/V", "m/s").front(), 5.0);
  EXPECT_GT(V0, 15.0);
  // the centre line's QSS lap from V0 (qss/*, on the flying bike's mesh, which is not the one
  // PeriodicQssSpeed used: the standing bike's refines the launch) arrives back at about V0
  EXPECT_NEAR(f.ReadVector("qss/V", "m/s").back(), V0, 0.01 * V0);
  const std::string yaml = f.ReadStringAttribute("bike_yaml"), key = "speed_m_per_s: ";
  ASSERT_NE(yaml.find(key), std::string::npos) << yaml;
  EXPECT_NEAR(std::stod(yaml.substr(yaml.find(key) + key.size())), V0, 1e-9 * V0) << yaml;
  EXPECT_LT(f.ReadDoubleAttribute("lap_time"), s.ReadDoubleAttribute("lap_time") - 1.0);

  const std::string straight = Road("straight100.h5", StraightRoad(100.0));
  ExpectBadInput(Lap(straight + " " + kBike + " --start flying"),
                 straight + ": --start flying needs a closed road");
}

// On a uniform 50 m mesh (--dt-max 0: two intervals, the first ~3 s long from 5 m/s) the oracle
// converges, but its states between nodes are too coarse for the launch: the re-simulation differs
// by more than 0.1 % (measured: the energy, 0.21 %) and the run exits 4.
TEST_F(LapCli, AConvergedSolveThatFailsTheReSimulationExits4) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const CliRun run = Lap(road + " " + kBike + " --ds 50 --dt-max 0 -q --solver ipopt");
  EXPECT_EQ(run.exit_code, 4) << run.stderr_text;
  EXPECT_EQ(std::count(run.stderr_text.begin(), run.stderr_text.end(), '\n'), 1) << run.stderr_text;
  EXPECT_NE(run.stderr_text.find("the solution failed its re-simulation check ("), std::string::npos)
      << run.stderr_text;
  EXPECT_TRUE(std::regex_search(run.stdout_text, std::regex("re-simulation  lap time differs by [0-9.]+ %, "
                                                            "states by [0-9.]+ % \\([A-Za-z_]+ at s = [0-9]+ m; failed\\)\n")))
      << run.stdout_text;
  const ttz::ArtefactReader r(Path("lap.h5"), "ttz.lap", 4);
  EXPECT_TRUE(r.ReadBoolAttribute("converged"));
  EXPECT_FALSE(r.ReadBoolAttribute("resim_passed"));
  EXPECT_GT(r.ReadDoubleAttribute("resim_max_state_difference"), 1e-3);
  EXPECT_EQ(r.ReadIntAttribute("nodes"), 3);
  // Where: the worst state's difference at each node, the largest of them the attribute's.
  const std::vector<double> worst = r.ReadVector("resim/" + r.ReadStringAttribute("resim_worst_state"), "1");
  ASSERT_EQ(worst.size(), 3u);
  EXPECT_EQ(worst[0], 0.0);
  EXPECT_EQ(*std::max_element(worst.begin(), worst.end()), r.ReadDoubleAttribute("resim_max_state_difference"));
}

// The same with the default --dt-max 0.25 s: the launch's intervals shrink to 0.25 s of the QSS
// speed, and the answer re-simulates.
TEST_F(LapCli, TheTimeLimitedMeshResolvesTheLaunch) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const CliRun run = Lap(road + " " + kBike + " --ds 50 -q --solver ipopt");
  EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
  const ttz::ArtefactReader r(Path("lap.h5"), "ttz.lap", 4);
  EXPECT_TRUE(r.ReadBoolAttribute("resim_passed"));
  EXPECT_GT(r.ReadIntAttribute("nodes"), 3);
  EXPECT_DOUBLE_EQ(r.ReadDoubleAttribute("mesh_ds"), 50.0);
  EXPECT_DOUBLE_EQ(r.ReadDoubleAttribute("mesh_dt_max"), 0.25);
  EXPECT_LT(r.ReadDoubleAttribute("mesh_ds_min"), 0.25 * 6.0);  // 0.25 s at the QSS speed near 5 m/s
}

// --init with the same road and mesh options solves on the earlier lap's mesh, and Ipopt starts
// from its states and its intervals' controls exactly: the same bike's lap restarts in under half
// the iterations to the same lap, and a neighbouring gear, whose own mesh differs at the launch,
// needs fewer iterations than from the QSS guess (measured: 74 cold, 49 warm, 17 to restart). The
// bike has the 90 V motor voltage limit and the c_r = 0 these figures were measured with
// (test_bike.h): with data/bx15.yaml's 80 V gear 3.4 rides the limit on this road, and warm and
// cold took 53 each.
TEST_F(LapCli, AnIpoptLapWarmStartsIpoptOnItsOwnMesh) {
  ttz::RoadArtefact bend = StraightRoad(500.0);  // a 50 m radius left bend from 300 to 380 m
  for (size_t i = 300; i <= 380; ++i) bend.kappa[i] = 1.0 / 50.0;
  const std::string road = Road("bend.h5", bend);
  const std::string options = road + " " + kBike + " --ds 10 -q --solver ipopt --set " +
                              ttz::lap::testing::kTestVoltageMaxSetting + " --set " +
                              ttz::lap::testing::kTestRollPriceSetting;
  const std::string gear = " --set drive.gear_ratio=3.4";
  // Exit 0 or 4: the bend's curvature steps from 0 to 1/50 m^-1, and z_dot does not re-simulate.
  auto solved = [&](const std::string& arguments, const std::string& output) {
    const int code = Lap(arguments, output).exit_code;
    return code == 0 || code == 4;
  };
  ASSERT_TRUE(solved(options, "a.h5"));
  ASSERT_TRUE(solved(options + " --init " + Path("a.h5"), "again.h5"));
  ASSERT_TRUE(solved(options + gear, "cold.h5"));
  ASSERT_TRUE(solved(options + gear + " --init " + Path("a.h5"), "warm.h5"));
  const ttz::ArtefactReader a(Path("a.h5"), "ttz.lap", 4), again(Path("again.h5"), "ttz.lap", 4),
      cold(Path("cold.h5"), "ttz.lap", 4), warm(Path("warm.h5"), "ttz.lap", 4);
  EXPECT_EQ(a.ReadStringAttribute("guess"), "centre-line");  // Ipopt's default (lap/main.cc)
  EXPECT_EQ(again.ReadVector("s", "m"), a.ReadVector("s", "m"));
  EXPECT_LT(again.ReadIntAttribute("iterations"), a.ReadIntAttribute("iterations") / 2);
  EXPECT_NEAR(again.ReadDoubleAttribute("lap_time"), a.ReadDoubleAttribute("lap_time"),
              1e-6 * a.ReadDoubleAttribute("lap_time"));
  EXPECT_NE(cold.ReadVector("s", "m"), a.ReadVector("s", "m"));
  EXPECT_EQ(warm.ReadVector("s", "m"), a.ReadVector("s", "m"));
  EXPECT_TRUE(warm.ReadBoolAttribute("mesh_from_init"));
  EXPECT_FALSE(cold.ReadBoolAttribute("mesh_from_init"));
  EXPECT_LT(warm.ReadIntAttribute("iterations"), cold.ReadIntAttribute("iterations"));
  EXPECT_NEAR(warm.ReadDoubleAttribute("lap_time"), cold.ReadDoubleAttribute("lap_time"),
              1e-3 * cold.ReadDoubleAttribute("lap_time"));
}

// A lap of one interval (--ds longer than the road, uniform) and a lap of schema version 2 (no
// control_interval/*) both warm-start a solve on another mesh.
TEST_F(LapCli, OneIntervalAndVersion2LapsWarmStart) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const std::string options = road + " " + kBike + " -q --solver ipopt";
  const int one = Lap(options + " --ds 200 --dt-max 0", "one.h5").exit_code;
  ASSERT_TRUE(one == 0 || one == 4);  // converged; the 100 m interval does not re-simulate
  ASSERT_EQ(ttz::ArtefactReader(Path("one.h5"), "ttz.lap", 4).ReadIntAttribute("nodes"), 2);
  EXPECT_EQ(Lap(options + " --ds 10 --init " + Path("one.h5"), "from_one.h5").exit_code, 0);

  ASSERT_EQ(Lap(options + " --ds 10", "v3.h5").exit_code, 0);
  ASSERT_NO_FATAL_FAILURE(AsAnOlderVersion(Path("v3.h5"), "control_interval", 2));
  const CliRun from_v2 = Lap(options + " --ds 10 --init " + Path("v3.h5"), "from_v2.h5");
  EXPECT_EQ(from_v2.exit_code, 0) << from_v2.stderr_text;
  EXPECT_TRUE(ttz::ArtefactReader(Path("from_v2.h5"), "ttz.lap", 4).ReadBoolAttribute("mesh_from_init"));
}

TEST_F(LapCli, ASolveThatDoesNotConvergeExits3AndStillWritesLapH5) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const CliRun run = Lap(road + " " + kBike + " --ds 4 -q --max-iterations 2");
  EXPECT_EQ(run.exit_code, 3) << run.stderr_text;
  EXPECT_EQ(std::count(run.stderr_text.begin(), run.stderr_text.end(), '\n'), 1) << run.stderr_text;
  EXPECT_NE(run.stderr_text.find("the solve did not converge (first step failed at eps 1, retried from the "
                                 "guess; continuation failed at eps 0.1;"),
            std::string::npos)
      << run.stderr_text;
  EXPECT_NE(run.stderr_text.find("--solver ipopt solves the same problem"), std::string::npos) << run.stderr_text;
  EXPECT_NE(run.stdout_text.find("converged      no ("), std::string::npos) << run.stdout_text;
  const ttz::ArtefactReader r(Path("lap.h5"), "ttz.lap", 4);
  EXPECT_FALSE(r.ReadBoolAttribute("converged"));
  EXPECT_NE(r.ReadStringAttribute("message").find("continuation failed"), std::string::npos);
}

// On a road longer than 5 km the indirect solver's first step is solved in the windows of the TT
// course (3000 m, overlapping by 500 m, 600 iterations for a window's first step) unless the
// command line says otherwise; lap.h5 records them. Where the bike has less than the price on
// rolling with which the solver has converged on long roads (data/bx15.yaml's 0.1), or the windows
// are switched off, the user is told before it starts; on a short road not.
TEST_F(LapCli, ARoadLongerThan5kmIsSolvedInWindows) {
  const std::string long_road = Road("straight6km.h5", StraightRoad(6000.0));
  const std::string warning = long_road + ": on a road longer than 5 km the indirect solver has converged only";
  const CliRun run = Lap(long_road + " " + kBike + " --ds 100 -q --max-iterations 1", "default.h5");
  EXPECT_EQ(run.exit_code, 3) << run.stderr_text;
  EXPECT_EQ(run.stderr_text.find(warning), std::string::npos) << run.stderr_text;
  const ttz::ArtefactReader windows(Path("default.h5"), "ttz.lap", 4);
  EXPECT_EQ(windows.ReadDoubleAttribute("window_m"), 3000.0);
  EXPECT_EQ(windows.ReadDoubleAttribute("window_overlap_m"), 500.0);
  // in one iteration the first window fails, and the whole road is solved from the guess
  EXPECT_FALSE(windows.ReadBoolAttribute("first_step_in_windows"));
  EXPECT_EQ(windows.ReadIntAttribute("max_iterations"), 1);  // given: not the long road's 600
  for (const std::string& other : {std::string(" --window 0"), std::string(" --set limits.roll_rate_weight_s2_per_rad2=0")}) {
    const CliRun warned = Lap(long_road + " " + kBike + " --ds 100 -q --max-iterations 1" + other, "other.h5");
    EXPECT_EQ(warned.exit_code, 3) << warned.stderr_text;
    EXPECT_NE(warned.stderr_text.find(warning), std::string::npos) << other << ": " << warned.stderr_text;
  }
  const std::string short_road = Road("straight100.h5", StraightRoad(100.0));
  EXPECT_EQ(Lap(short_road + " " + kBike + " --ds 4 -q --max-iterations 1").stderr_text.find("longer than 5 km"),
            std::string::npos);
}

// An option of the solver not chosen is said to have no effect (one warning line each), and the
// chosen solver's own options are not.
TEST_F(LapCli, TheOtherSolversOptionsAreSaidToHaveNoEffect) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const std::string args = road + " " + kBike + " --ds 4 -q --max-iterations 1";
  const CliRun indirect = Lap(args + " --mu-init 1e-3 --window 50 --window-overlap 10");
  EXPECT_NE(indirect.stderr_text.find("lap: warning: --mu-init is an option of --solver ipopt: it has no effect on this "
                                      "solve (--solver indirect)\n"),
            std::string::npos)
      << indirect.stderr_text;
  EXPECT_EQ(indirect.stderr_text.find("--window"), std::string::npos) << indirect.stderr_text;
  const CliRun ipopt = Lap(args + " --solver ipopt --window-eps 0.1 --mu-strategy monotone");
  EXPECT_NE(ipopt.stderr_text.find("--window-eps is an option of the indirect solver: it has no effect on this solve "
                                   "(--solver ipopt)"),
            std::string::npos)
      << ipopt.stderr_text;
  EXPECT_EQ(ipopt.stderr_text.find("--mu-strategy"), std::string::npos) << ipopt.stderr_text;
}

// Ipopt's options file in the working directory is ignored: this one would stop it after 1 iteration.
TEST_F(LapCli, AnIpoptOptFileInTheWorkingDirectoryIsIgnored) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  File("ipopt.opt", "max_iter 1\n");
  const std::string command = "cd " + dir_.string() + " && " + kLap + " " + road + " " + kBike +
                              " --solver ipopt --ds 4 -q -o " + Path("lap.h5") + " > /dev/null 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(command.c_str())), 0);
  EXPECT_GT(ttz::ArtefactReader(Path("lap.h5"), "ttz.lap", 4).ReadIntAttribute("iterations"), 1);
}

TEST_F(LapCli, AnIpoptSolveThatDoesNotConvergeExits3WithoutTheHintToUseIpopt) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const CliRun run = Lap(road + " " + kBike + " --ds 4 -q --solver ipopt --max-iterations 2");
  EXPECT_EQ(run.exit_code, 3) << run.stderr_text;
  EXPECT_NE(run.stderr_text.find("the solve did not converge ("), std::string::npos) << run.stderr_text;
  EXPECT_EQ(run.stderr_text.find("--solver ipopt"), std::string::npos) << run.stderr_text;
}

TEST_F(LapCli, RoadMissing) {
  ExpectBadInput(Lap(Path("none.h5") + " " + kBike), Path("none.h5") + ": file not found");
}

TEST_F(LapCli, RoadOfAnotherSchema) {
  ExpectBadInput(Lap(kBike + " " + kBike), kBike + ": not an HDF5 file (a ttz.road artefact expected)");
  {
    ttz::ArtefactWriter w(Path("a_lap.h5"), "ttz.lap", 4);
    w.Commit();
  }
  ExpectBadInput(Lap(Path("a_lap.h5") + " " + kBike),
                 Path("a_lap.h5") + ": schema 'ttz.lap' found, 'ttz.road' expected");
}

TEST_F(LapCli, RoadOfAnotherSchemaVersion) {
  {
    ttz::ArtefactWriter w(Path("road.h5"), "ttz.road", 3);
    w.Commit();
  }
  ExpectBadInput(Lap(Path("road.h5") + " " + kBike), Path("road.h5") + ": schema_version 3 found, 1 to 2 expected");
}

// A road.h5 of version 1, before banking, is a road level across: the same lap as version 2's.
TEST_F(LapCli, AVersion1RoadIsLevelAcross) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  const std::string options = " " + kBike + " -q --ds 10";
  ASSERT_EQ(Lap(road + options, "v2.h5").exit_code, 0);
  ASSERT_NO_FATAL_FAILURE(AsAnOlderVersion(road, "banking", 1));
  const CliRun v1 = Lap(road + options, "v1.h5");
  ASSERT_EQ(v1.exit_code, 0) << v1.stderr_text;
  EXPECT_EQ(ttz::ArtefactReader(Path("v1.h5"), "ttz.lap", 4).ReadDoubleAttribute("lap_time"),
            ttz::ArtefactReader(Path("v2.h5"), "ttz.lap", 4).ReadDoubleAttribute("lap_time"));
}

TEST_F(LapCli, RoadWithoutCurvature) {
  const ttz::RoadArtefact road = StraightRoad(100.0);
  {
    ttz::ArtefactWriter w(Path("road.h5"), "ttz.road", 1);
    for (const auto& [name, values, units] :
         {std::tuple{"s", &road.s, "m"}, {"x", &road.x, "m"}, {"y", &road.y, "m"}, {"z", &road.z, "m"},
          {"theta", &road.theta, "rad"}, {"sigma", &road.sigma, "rad"}, {"width", &road.width, "m"}})
      w.WriteVector(name, *values, units, "test");
    w.Commit();
  }
  ExpectBadInput(Lap(Path("road.h5") + " " + kBike), Path("road.h5") + ": dataset 'kappa' is missing");
}

TEST_F(LapCli, BikeWithAnUnknownKey) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  const std::string bike = Bike("chassis:\n", "chassis:\n  wing_area_m2: 1\n");
  ExpectBadInput(Lap(road + " " + bike), bike + ":7: key 'chassis.wing_area_m2': unknown key");
}

TEST_F(LapCli, BikeWithAMissingKey) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  const std::string text = ReadText(kBike);
  const size_t at = text.find("  cog_height_m:");
  const std::string bike = Bike(text.substr(at, text.find('\n', at) + 1 - at), "");
  ExpectBadInput(Lap(road + " " + bike), "key 'chassis.cog_height_m': missing key");
}

TEST_F(LapCli, EfficiencyAboveOneBySet) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  ExpectBadInput(Lap(road + " " + kBike + " --set controller.efficiency=1.2"),
                 "override 'controller.efficiency=1.2': key 'controller.efficiency': non-physical value 1.2");
}

TEST_F(LapCli, InitialSpeedZero) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  ExpectBadInput(Lap(road + " " + kBike + " --set initial.speed_m_per_s=0"),
                 "key 'initial.speed_m_per_s': non-physical value 0");
}

TEST_F(LapCli, RoadNarrowerThanTheBikeCanUse) {
  // 0.9 m wide from s = 100 to 110 m; border_margin_m = 0.5 needs more than 1 m.
  const std::string road = Road("narrow.h5", StraightRoad(200.0, [](double s) {
    return s >= 100.0 && s <= 110.0 ? 0.9 : 8.0;
  }));
  ExpectBadInput(Lap(road + " " + kBike), road + ": road width 0.9 m at s = 100 m leaves the bike no room");
}

TEST_F(LapCli, InitFromARoadArtefact) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  ExpectBadInput(Lap(road + " " + kBike + " --init " + road), road + ": schema 'ttz.road' found, 'ttz.lap' expected");
}

TEST_F(LapCli, UnwritableOutputFolder) {
  const std::string road = Road("road.h5", StraightRoad(100.0));
  const CliRun run = Lap(road + " " + kBike, "missing-folder/lap.h5");
  ExpectBadInput(run, "missing-folder/lap.h5: cannot be written", "missing-folder/lap.h5");
}

// --mu-globalization reaches Ipopt (a value it rejects would throw, ipopt_direct_test) and either
// value ends on the same lap here.
TEST_F(LapCli, BothMuGlobalizationsSolveTheSameLap) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const std::string options = road + " " + kBike + " --ds 4 -q --solver ipopt --mu-globalization ";
  const CliRun filter = Lap(options + "obj-constr-filter", "filter.h5");
  const CliRun kkt = Lap(options + "kkt-error", "kkt.h5");
  ASSERT_EQ(filter.exit_code, 0) << filter.stderr_text;
  ASSERT_EQ(kkt.exit_code, 0) << kkt.stderr_text;
  const ttz::ArtefactReader filter_h5(Path("filter.h5"), "ttz.lap", 4), kkt_h5(Path("kkt.h5"), "ttz.lap", 4);
  const double t_filter = filter_h5.ReadDoubleAttribute("lap_time");
  EXPECT_NEAR(kkt_h5.ReadDoubleAttribute("lap_time"), t_filter, 1e-6 * t_filter);
  EXPECT_EQ(filter_h5.ReadStringAttribute("mu_globalization"), "obj-constr-filter");
  EXPECT_EQ(kkt_h5.ReadStringAttribute("mu_globalization"), "kkt-error");
}

// The monotone barrier from a small mu_init, what docs/lap.md uses from a neighbouring lap (--init).
TEST_F(LapCli, AMonotoneBarrierFromTheLapItselfSolvesTheSameLap) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  const std::string options = road + " " + kBike + " --ds 4 -q --solver ipopt";
  ASSERT_EQ(Lap(options, "adaptive.h5").exit_code, 0);
  const CliRun monotone =
      Lap(options + " --init " + Path("adaptive.h5") + " --mu-strategy monotone --mu-init 1e-4", "monotone.h5");
  ASSERT_EQ(monotone.exit_code, 0) << monotone.stderr_text;
  const ttz::ArtefactReader adaptive_h5(Path("adaptive.h5"), "ttz.lap", 4);
  const ttz::ArtefactReader monotone_h5(Path("monotone.h5"), "ttz.lap", 4);
  const double t = adaptive_h5.ReadDoubleAttribute("lap_time");
  EXPECT_NEAR(monotone_h5.ReadDoubleAttribute("lap_time"), t, 1e-6 * t);
  EXPECT_EQ(adaptive_h5.ReadStringAttribute("mu_strategy"), "adaptive");
  EXPECT_EQ(monotone_h5.ReadStringAttribute("mu_strategy"), "monotone");
  EXPECT_EQ(monotone_h5.ReadDoubleAttribute("mu_init"), 1e-4);
}

TEST_F(LapCli, LapH5RecordsTheIterationLimitInEffect) {
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  ASSERT_EQ(Lap(road + " " + kBike + " --ds 4 -q --solver ipopt", "ipopt.h5").exit_code, 0);
  ASSERT_EQ(Lap(road + " " + kBike + " --ds 4 -q --max-iterations 250", "indirect.h5").exit_code, 0);
  const ttz::ArtefactReader ipopt(Path("ipopt.h5"), "ttz.lap", 4), indirect(Path("indirect.h5"), "ttz.lap", 4);
  EXPECT_EQ(ipopt.ReadIntAttribute("max_iterations"), ttz::lap::IpoptOptions{}.max_iterations);
  EXPECT_EQ(indirect.ReadIntAttribute("max_iterations"), 250);
  EXPECT_EQ(indirect.ReadStringAttribute("mu_globalization"), "");
}

// --window solves the first step window by window (IndirectOptions::window_m); lap.h5 says so.
TEST_F(LapCli, TheIndirectSolverSolvesInWindowsWhenAsked) {
  const std::string road = Road("straight400.h5", StraightRoad(400.0));
  ASSERT_EQ(Lap(road + " " + kBike + " --ds 4 -q", "whole.h5").exit_code, 0);
  const CliRun run = Lap(road + " " + kBike + " --ds 4 -q --window 200 --window-overlap 50", "windows.h5");
  ASSERT_EQ(run.exit_code, 0) << run.stderr_text << run.stdout_text;
  const ttz::ArtefactReader whole(Path("whole.h5"), "ttz.lap", 4), windows(Path("windows.h5"), "ttz.lap", 4);
  EXPECT_EQ(whole.ReadDoubleAttribute("window_m"), 0.0);
  EXPECT_EQ(whole.ReadDoubleAttribute("window_overlap_m"), 0.0);
  EXPECT_FALSE(whole.ReadBoolAttribute("first_step_in_windows"));
  EXPECT_TRUE(windows.ReadBoolAttribute("first_step_in_windows"));
  EXPECT_EQ(windows.ReadDoubleAttribute("window_m"), 200.0);
  EXPECT_EQ(windows.ReadDoubleAttribute("window_overlap_m"), 50.0);
  EXPECT_EQ(whole.ReadDoubleAttribute("window_eps_end"), 0.0);
  EXPECT_EQ(windows.ReadDoubleAttribute("window_eps_end"), ttz::lap::IndirectOptions{}.window_eps_end);
  // the QSS lap's price on charge (QssChargePrice): ~0, the full pack lasts this lap at full power
  EXPECT_EQ(whole.ReadDoubleAttribute("window_charge_price"), 0.0);
  EXPECT_NEAR(windows.ReadDoubleAttribute("window_charge_price"), 0.0, 1e-8);
  // a warm start has costates: its first step is not solved in windows, and lap.h5 says so
  ASSERT_EQ(Lap(road + " " + kBike + " --ds 4 -q --window 200 --window-overlap 50 --init " + Path("windows.h5"),
                "warm.h5").exit_code, 0);
  const ttz::ArtefactReader warm(Path("warm.h5"), "ttz.lap", 4);
  EXPECT_EQ(warm.ReadDoubleAttribute("window_m"), 200.0);
  EXPECT_FALSE(warm.ReadBoolAttribute("first_step_in_windows"));
  // more steps than the whole road's continuation: the windows' come first (SolveSummary::steps)
  EXPECT_GT(windows.ReadVector("continuation/eps", "1").size(), whole.ReadVector("continuation/eps", "1").size());
  EXPECT_NEAR(windows.ReadDoubleAttribute("lap_time"), whole.ReadDoubleAttribute("lap_time"),
              1e-6 * whole.ReadDoubleAttribute("lap_time"));
}

TEST_F(LapCli, BadOptions) {
  ExpectBadInput(Lap("road.h5 bike.yaml --ds -1"), "--ds");
  ExpectBadInput(Lap("road.h5 bike.yaml --solver newton"), "--solver");
  ExpectBadInput(Lap("road.h5 bike.yaml --guess apex"), "--guess");
  ExpectBadInput(Lap("road.h5 bike.yaml --mu-globalization never"), "--mu-globalization");
  ExpectBadInput(Lap("road.h5 bike.yaml --mu-strategy sometimes"), "--mu-strategy");
  ExpectBadInput(Lap("road.h5 bike.yaml --mu-init 0"), "--mu-init");
  ExpectBadInput(Lap("road.h5 bike.yaml --dt-max -0.5"), "--dt-max: value -0.5 is not a non-negative number");
  ExpectBadInput(Lap("road.h5 bike.yaml --window -1"), "--window: value -1 is not a non-negative number");
  ExpectBadInput(Lap("road.h5 bike.yaml --window-eps 0"), "--window-eps: value 0 is not a positive number");
  const std::string road = Road("straight100.h5", StraightRoad(100.0));
  ExpectBadInput(Lap(road + " " + kBike + " --window 500 --window-overlap 500"),
                 "--window-overlap: 500 m, expected less than --window (500 m)");
}

}  // namespace
