// Tests of lap/bike.h: the BX-15 file (data/bx15.yaml), the derived figures against hand
// calculations, the YAML round trip, and every kind of input error with its key and line.
#include "lap/bike.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"

namespace ttz::lap {
namespace {

const std::string kName = "test.yaml";  // the file name ParseBike puts in its messages

std::string Bx15Path() { return std::string(TTZ_SOURCE_DIR) + "/data/bx15.yaml"; }

BikeParams Bx15(const std::vector<std::string>& overrides = {}) {
  return LoadBike(Bx15Path(), overrides);
}

// Substring checks of an error message (plain GoogleTest, no gmock needed).
#define EXPECT_CONTAINS(text, part)                                  \
  EXPECT_TRUE(std::string(text).find(part) != std::string::npos) \
      << "wanted \"" << (part) << "\" in: " << (text)
#define EXPECT_LACKS(text, part)                                     \
  EXPECT_TRUE(std::string(text).find(part) == std::string::npos) \
      << "did not want \"" << (part) << "\" in: " << (text)

// EXPECT_NEAR with a relative tolerance.
void ExpectRel(double actual, double expected, double rel = 1e-12) {
  EXPECT_NEAR(actual, expected, rel * std::fabs(expected)) << "expected " << expected;
}

// ---- Editing bike.yaml text line by line -------------------------------------------------------

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Text(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  return text;
}

// 0-based index of the line "section:" in the layout BikeToYaml writes; -1 when absent.
int SectionIndex(const std::vector<std::string>& lines, const std::string& section) {
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i] == section + ":") return static_cast<int>(i);
  return -1;
}

// 0-based index of the line "  key: ..." of `path` ("section.key"); fails the test when absent.
int KeyIndex(const std::vector<std::string>& lines, const std::string& path) {
  const auto dot = path.find('.');
  const std::string section = path.substr(0, dot), key = path.substr(dot + 1);
  const int s = SectionIndex(lines, section);
  if (s >= 0)
    for (size_t i = s + 1; i < lines.size() && lines[i].rfind("  ", 0) == 0; ++i)
      if (lines[i].rfind("  " + key + ":", 0) == 0) return static_cast<int>(i);
  ADD_FAILURE() << "no line for key " << path;
  return -1;
}

// The value text of a "  key: value  # comment" line.
std::string ValueOf(const std::string& line) {
  const auto colon = line.find(':');
  const auto hash = line.find('#');
  std::string v = line.substr(colon + 1, hash == std::string::npos ? std::string::npos
                                                                     : hash - colon - 1);
  const auto b = v.find_first_not_of(' '), e = v.find_last_not_of(' ');
  return v.substr(b, e - b + 1);
}

void SetValue(std::vector<std::string>* lines, const std::string& path, const std::string& value) {
  const int i = KeyIndex(*lines, path);
  const std::string& line = (*lines)[i];
  const std::string key = line.substr(0, line.find(':'));
  (*lines)[i] = key + ": " + value + "  # edited by the test";
}

// Text of the BX-15 in BikeToYaml's layout, with one value replaced; *line gets its 1-based line.
std::string Bx15WithValue(const std::string& path, const std::string& value, int* line) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  SetValue(&lines, path, value);
  *line = KeyIndex(lines, path) + 1;
  return Text(lines);
}

// Parses `text` and returns the InputError's message ("" and a test failure when it parses).
std::string ErrorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    ParseBike(text, kName, overrides);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

std::string At(int line, const std::string& path) {
  return kName + ":" + std::to_string(line) + ": key '" + path + "'";
}

// ---- The BX-15 file -------------------------------------------------------------------------

TEST(BikeTest, Bx15Loads) {
  const BikeParams p = Bx15();
  EXPECT_EQ(p.motor.count, 2);
  EXPECT_EQ(p.battery.cells_series, 24);
  EXPECT_EQ(p.battery.cells_parallel, 4);
  EXPECT_EQ(p.tyre.r, 0.3);     // Table A1 swaps r and r_t (docs/bike.md)
  EXPECT_EQ(p.tyre.r_t, 0.1);
  EXPECT_EQ(p.drive.gamma_c, 2.8);
  EXPECT_EQ(p.chassis.I_xx, 19.0);
  EXPECT_EQ(p.aero.C_d, 0.41);
  EXPECT_EQ(p.motor.current_max, 600.0);
  EXPECT_GT(p.initial.V, 0.0);  // the model needs V > 0 (eq. 36)
}

TEST(BikeTest, Bx15HasOneSourceCommentPerValueInTableOrder) {
  std::ifstream in(Bx15Path());
  ASSERT_TRUE(in) << Bx15Path();
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  const std::vector<std::string> keys = BikeKeys();
  size_t next = 0;
  std::string section;
  for (const std::string& l : lines) {
    if (l.empty() || l[0] == '#') continue;
    if (l[0] != ' ') {  // a section line
      section = l.substr(0, l.find(':'));
      continue;
    }
    ASSERT_LT(next, keys.size()) << "extra line: " << l;
    const std::string key = l.substr(2, l.find(':') - 2);
    EXPECT_EQ(section + "." + key, keys[next]) << "line: " << l;
    EXPECT_NE(l.find("  # "), std::string::npos) << "no source comment: " << l;
    ++next;
  }
  EXPECT_EQ(next, keys.size());
}

TEST(BikeTest, Bx15TotalMassIs290) {
  // 168 kg base + 2 x 11 kg motors + 51 MJ / 0.51 MJ/kg = 100 kg pack (Table A1: M = 290 kg).
  const BikeParams p = Bx15();
  EXPECT_NEAR(TotalMass(p), 290.0, 290.0 * 1e-9);
  ExpectRel(Pack(p).mass, 100.0);
}

TEST(BikeTest, Bx15PackFigures) {
  const BikeParams p = Bx15();
  const PackFigures f = Pack(p);
  ExpectRel(f.V_bn1, 24 * 4.15);           // 99.6 V
  ExpectRel(f.V_bn0, 24 * 3.5);            // 84 V
  ExpectRel(f.R_b, 24 * 0.0012 / 4);       // 7.2 mOhm: 24 cells in series, 4 strings in parallel
  ExpectRel(f.e_i, 51e6);                  // 96 cells x 531250 J
  ExpectRel(f.mass, 51e6 / 0.51e6);        // 100 kg
  ExpectRel(InitialEnergy(p), 51e6);       // state of charge 1
  const BikeParams half = Bx15({"initial.state_of_charge=0.5"});
  ExpectRel(InitialEnergy(half), 25.5e6);
}

TEST(BikeTest, PackFiguresOfAnArbitraryArrangement) {
  BikeParams p = Bx15();
  p.battery.cells_series = 10;
  p.battery.cells_parallel = 3;
  p.battery.cell_ocv_full = 4.0;
  p.battery.cell_ocv_empty = 3.0;
  p.battery.cell_resistance = 0.003;
  p.battery.cell_energy = 1000.0;
  p.battery.energy_density = 500.0;
  const PackFigures f = Pack(p);
  ExpectRel(f.V_bn1, 40.0);
  ExpectRel(f.V_bn0, 30.0);
  ExpectRel(f.R_b, 0.01);
  ExpectRel(f.e_i, 30000.0);
  ExpectRel(f.mass, 60.0);
}

// ---- Motors in parallel ---------------------------------------------------------------------

TEST(BikeTest, MotorsInParallelHalvesResistanceForTwo) {
  const BikeParams p = Bx15();
  const MotorParams& m = p.motor;
  ASSERT_EQ(m.count, 2);
  const EquivalentMotor e = MotorsInParallel(p);
  ExpectRel(e.R_m0, m.R_m0 / 2);
  ExpectRel(e.sigma_R, m.sigma_R / 2);
  EXPECT_EQ(e.k_V0, m.k_V0);
  EXPECT_EQ(e.k_tau0, m.k_tau0);
  EXPECT_EQ(e.sigma_m, m.sigma_m);
  ExpectRel(e.i_m0, 2 * m.i_m0);
  ExpectRel(e.current_max, 1200.0);  // the Kelly KDHE's 1200 A
  EXPECT_EQ(e.voltage_max, m.voltage_max);
  EXPECT_EQ(e.T_0, m.T_0);
  ExpectRel(e.C, 2 * m.C);
  ExpectRel(e.q_0, 2 * m.q_0);
  ExpectRel(e.q_1, 2 * m.q_1);
  EXPECT_EQ(e.V_1, m.V_1);
}

TEST(BikeTest, MotorsInParallelTriplesCurrentForThree) {
  const BikeParams p = Bx15({"motor.count=3"});
  const MotorParams& m = p.motor;
  ASSERT_EQ(m.count, 3);
  const EquivalentMotor e = MotorsInParallel(p);
  ExpectRel(e.current_max, 3 * m.current_max);  // 1800 A
  ExpectRel(e.R_m0, m.R_m0 / 3);
  ExpectRel(e.sigma_R, m.sigma_R / 3);
  ExpectRel(e.i_m0, 3 * m.i_m0);
  ExpectRel(e.C, 3 * m.C);
  ExpectRel(e.q_0, 3 * m.q_0);
  ExpectRel(e.q_1, 3 * m.q_1);
  EXPECT_EQ(e.k_V0, m.k_V0);
  EXPECT_EQ(e.k_tau0, m.k_tau0);
}

TEST(BikeTest, EquivalentMotorGivesTheSameVoltageAndTorqueAsTheMotors) {
  // n motors at speed w each carrying i/n: V = (i/n) R + k_V w and tau = n k_tau (i/n - i_m0).
  for (int n : {1, 2, 3}) {
    const BikeParams p = Bx15({"motor.count=" + std::to_string(n)});
    const EquivalentMotor e = MotorsInParallel(p);
    const double i = 900.0, w = 400.0;
    const MotorParams& m = p.motor;
    ExpectRel(i * e.R_m0 + e.k_V0 * w, (i / n) * m.R_m0 + m.k_V0 * w);
    ExpectRel(e.k_tau0 * (i - e.i_m0), n * m.k_tau0 * (i / n - m.i_m0));
  }
}

// ---- Derived masses follow the design studies (paper sec 5) ----------------------------------

TEST(BikeTest, ThirdMotorByOverrideAddsElevenKilograms) {
  const BikeParams two = Bx15();
  const BikeParams three = Bx15({"motor.count=3"});
  EXPECT_EQ(three.motor.count, 3);
  ExpectRel(TotalMass(three) - TotalMass(two), 11.0);
  ExpectRel(TotalMass(three), 301.0);
}

TEST(BikeTest, FifthParallelStringAddsTheMassOfOneString) {
  const BikeParams four = Bx15();
  const BikeParams five = Bx15({"battery.cells_parallel=5"});
  const double string_mass = 24 * four.battery.cell_energy / four.battery.energy_density;  // 25 kg
  ExpectRel(TotalMass(five) - TotalMass(four), string_mass);
  ExpectRel(string_mass, 25.0);
  ExpectRel(Pack(five).e_i, 63.75e6);  // paper Table 1: 5P24S = 64 MJ
  ExpectRel(Pack(five).R_b, 24 * 0.0012 / 5);
  ExpectRel(Pack(five).V_bn1, Pack(four).V_bn1);
}

// ---- Round trip -----------------------------------------------------------------------------

TEST(BikeTest, BikeToYamlRoundTripsTheBx15) {
  const BikeParams p = Bx15();
  const std::string text = BikeToYaml(p);
  const BikeParams q = ParseBike(text, kName);
  EXPECT_EQ(BikeToYaml(q), text);
  // The file's own values read back the same through the text.
  const std::vector<std::string> a = Lines(text);
  std::ifstream in(Bx15Path());
  std::vector<std::string> file;
  for (std::string l; std::getline(in, l);) file.push_back(l);
  for (const std::string& path : BikeKeys()) {
    EXPECT_EQ(std::strtod(ValueOf(a[KeyIndex(a, path)]).c_str(), nullptr),
              std::strtod(ValueOf(file[KeyIndex(file, path)]).c_str(), nullptr))
        << path;
  }
}

TEST(BikeTest, BikeToYamlRoundTripsEveryKeyExactly) {
  // Every real value moved to a neighbouring double that needs all 17 digits, every integer
  // changed: parsing BikeToYaml's text must give back exactly these values, key by key.
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  std::vector<double> wanted;
  int k = 0;
  for (const std::string& path : BikeKeys()) {
    const std::string old = ValueOf(lines[KeyIndex(lines, path)]);
    const bool integer = old.find_first_not_of("0123456789") == std::string::npos &&
                         (path == "motor.count" || path.find("cells_") != std::string::npos);
    double v;
    char buf[40];
    if (integer) {
      v = std::strtod(old.c_str(), nullptr) + 1 + (k % 3);
      std::snprintf(buf, sizeof buf, "%d", static_cast<int>(v));
    } else {
      const double x = std::strtod(old.c_str(), nullptr);
      v = (path == "initial.state_of_charge" || path.find("efficiency") != std::string::npos)
              ? std::nextafter(x, 0.0) * (0.9 + 0.01 * (k % 7))  // stays in (0, 1]
              : std::nextafter(x * (1.0 + 1.0 / (3.0 + k)), HUGE_VAL);
      std::snprintf(buf, sizeof buf, "%.17g", v);
    }
    SetValue(&lines, path, buf);
    wanted.push_back(std::strtod(buf, nullptr));
    ++k;
  }
  const BikeParams p = ParseBike(Text(lines), kName);
  const std::string text = BikeToYaml(p);
  const BikeParams q = ParseBike(text, kName);
  EXPECT_EQ(BikeToYaml(q), text);
  const std::vector<std::string> out = Lines(text);
  const std::vector<std::string> keys = BikeKeys();
  ASSERT_EQ(keys.size(), wanted.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    const std::string& path = keys[i];
    EXPECT_EQ(std::strtod(ValueOf(out[KeyIndex(out, path)]).c_str(), nullptr), wanted[i])
        << path << " written as " << out[KeyIndex(out, path)];
  }
  // Spot checks through the struct itself.
  EXPECT_EQ(q.chassis.base_mass, p.chassis.base_mass);
  EXPECT_EQ(q.tyre.K_kappa, p.tyre.K_kappa);
  EXPECT_EQ(q.motor.V_1, p.motor.V_1);
  EXPECT_EQ(q.battery.cell_energy, p.battery.cell_energy);
  EXPECT_EQ(q.motor.count, p.motor.count);
  EXPECT_EQ(q.battery.cells_parallel, p.battery.cells_parallel);
}

TEST(BikeTest, BikeKeysMatchTheLayoutOfBikeToYaml) {
  const std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  int previous = -1;
  for (const std::string& path : BikeKeys()) {
    const int i = KeyIndex(lines, path);
    EXPECT_GT(i, previous) << path;  // file order
    previous = i;
  }
}

// ---- Errors: key path and line --------------------------------------------------------------

TEST(BikeTest, UnknownKeyNamesKeyAndLine) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int after = KeyIndex(lines, "tyre.lateral_adherence");
  lines.insert(lines.begin() + after + 1, "  lateral_grip: 0.7");
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, At(after + 2, "tyre.lateral_grip"));
  EXPECT_CONTAINS(msg, "unknown key");
}

TEST(BikeTest, UnknownSectionNamesSectionAndLine) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  lines.push_back("rider:");
  lines.push_back("  name: x");
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, At(static_cast<int>(lines.size()) - 1, "rider"));
  EXPECT_CONTAINS(msg, "unknown section");
}

TEST(BikeTest, KeyGivenTwiceNamesTheSecondLine) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int first = KeyIndex(lines, "aero.drag_area_m2");
  lines.insert(lines.begin() + first + 1, "  drag_area_m2: 0.5");
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, At(first + 2, "aero.drag_area_m2"));
  EXPECT_CONTAINS(msg, "twice");
}

TEST(BikeTest, MissingKeyNamesKeyAndItsSection) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int i = KeyIndex(lines, "motor.thermal_capacity_j_per_k");
  lines.erase(lines.begin() + i);
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, "key 'motor.thermal_capacity_j_per_k'");
  EXPECT_CONTAINS(msg, "missing key");
  // The line is the section's header, "motor:".
  const int section_line = SectionIndex(lines, "motor") + 1;
  EXPECT_CONTAINS(msg, At(section_line, "motor.thermal_capacity_j_per_k"));
}

TEST(BikeTest, MissingSectionNamesItsFirstKey) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int s = SectionIndex(lines, "controller");
  lines.erase(lines.begin() + s, lines.begin() + s + 2);  // "controller:" and its one key
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, kName + ": key 'controller.efficiency'");
  EXPECT_CONTAINS(msg, "no section 'controller'");
}

TEST(BikeTest, MissingValueNamesKeyAndLine) {
  int line = 0;
  const std::string text = Bx15WithValue("drive.gear_ratio", "", &line);
  const std::string msg = ErrorOf(text);
  EXPECT_CONTAINS(msg, At(line, "drive.gear_ratio"));
  EXPECT_CONTAINS(msg, "missing value");
}

TEST(BikeTest, WrongTypeNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("chassis.cog_height_m", "abc", &line));
  EXPECT_CONTAINS(msg, At(line, "chassis.cog_height_m"));
  EXPECT_CONTAINS(msg, "expected a number, got 'abc'");
}

TEST(BikeTest, ListInsteadOfNumberNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("aero.lift_area_m2", "[1, 2]", &line));
  EXPECT_CONTAINS(msg, At(line, "aero.lift_area_m2"));
  EXPECT_CONTAINS(msg, "expected a number");
}

TEST(BikeTest, FractionForAnIntegerNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("motor.count", "2.5", &line));
  EXPECT_CONTAINS(msg, At(line, "motor.count"));
  EXPECT_CONTAINS(msg, "expected an integer, got '2.5'");
}

TEST(BikeTest, NonFiniteNumberNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("tyre.radial_stiffness_n_per_m", ".inf", &line));
  EXPECT_CONTAINS(msg, At(line, "tyre.radial_stiffness_n_per_m"));
  EXPECT_CONTAINS(msg, "finite");
}

TEST(BikeTest, NegativeMassNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("motor.mass_kg", "-11", &line));
  EXPECT_CONTAINS(msg, At(line, "motor.mass_kg"));
  EXPECT_CONTAINS(msg, "non-physical value -11");
  EXPECT_CONTAINS(msg, "> 0");
}

TEST(BikeTest, NegativeBaseMassNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("chassis.base_mass_kg", "-168", &line));
  EXPECT_CONTAINS(msg, At(line, "chassis.base_mass_kg"));
  EXPECT_CONTAINS(msg, "non-physical");
}

TEST(BikeTest, EfficiencyAboveOneNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("controller.efficiency", "1.2", &line));
  EXPECT_CONTAINS(msg, At(line, "controller.efficiency"));
  EXPECT_CONTAINS(msg, "non-physical value 1.2");
  EXPECT_CONTAINS(msg, "(0, 1]");
  // 1 itself is allowed.
  int unused = 0;
  EXPECT_NO_THROW(ParseBike(Bx15WithValue("controller.efficiency", "1", &unused), kName));
}

TEST(BikeTest, ZeroMotorsNamesKeyAndLine) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("motor.count", "0", &line));
  EXPECT_CONTAINS(msg, At(line, "motor.count"));
  EXPECT_CONTAINS(msg, "non-physical");
}

TEST(BikeTest, ZeroInitialSpeedIsRejected) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("initial.speed_m_per_s", "0", &line));
  EXPECT_CONTAINS(msg, At(line, "initial.speed_m_per_s"));
}

TEST(BikeTest, SwappedTyreRadiiAreRejectedAtTheToroidRadius) {
  // Table A1's literal r = 0.1 m, r_t = 0.3 m.
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  SetValue(&lines, "tyre.wheel_radius_m", "0.1");
  SetValue(&lines, "tyre.toroid_radius_m", "0.3");
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, At(KeyIndex(lines, "tyre.toroid_radius_m") + 1,
                                "tyre.toroid_radius_m"));
  EXPECT_CONTAINS(msg, "r_t < r");
}

TEST(BikeTest, TorqueConstantAboveBackEmfConstantIsRejected) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("motor.torque_constant_n_m_per_a", "0.2", &line));
  EXPECT_CONTAINS(msg, At(line, "motor.torque_constant_n_m_per_a"));
}

TEST(BikeTest, EmptyOcvRangeIsRejected) {
  int line = 0;
  const std::string msg = ErrorOf(Bx15WithValue("battery.cell_ocv_empty_v", "4.2", &line));
  EXPECT_CONTAINS(msg, At(line, "battery.cell_ocv_empty_v"));
}

TEST(BikeTest, YamlSyntaxErrorNamesTheLine) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int i = KeyIndex(lines, "battery.cell_energy_j");
  lines[i] = "  cell_energy_j: [531250";  // unclosed flow sequence
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, "YAML syntax error");
  // yaml-cpp reports an unclosed flow sequence where it notices it: on that line or the next.
  EXPECT_TRUE(msg.rfind(kName + ":" + std::to_string(i + 1) + ":", 0) == 0 ||
              msg.rfind(kName + ":" + std::to_string(i + 2) + ":", 0) == 0)
      << msg;
}

TEST(BikeTest, YamlBadIndentationNamesTheLine) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int i = KeyIndex(lines, "drive.efficiency");
  lines[i] = "     efficiency: 0.95";  // deeper than its sibling: a syntax error here
  const std::string msg = ErrorOf(Text(lines));
  EXPECT_CONTAINS(msg, "YAML syntax error");
  EXPECT_EQ(msg.rfind(kName + ":" + std::to_string(i + 1) + ":", 0), 0u) << msg;
}

TEST(BikeTest, NotAMapIsAnError) {
  const std::string msg = ErrorOf("- a\n- b\n");
  EXPECT_CONTAINS(msg, "expected a map of sections");
  const std::string msg2 = ErrorOf("chassis: 3\n");
  EXPECT_CONTAINS(msg2, At(1, "chassis"));
}

TEST(BikeTest, EmptyFileNamesTheFirstMissingKey) {
  const std::string msg = ErrorOf("");
  EXPECT_CONTAINS(msg, "key '" + BikeKeys().front() + "'");
}

// ---- Overrides ------------------------------------------------------------------------------

TEST(BikeTest, OverrideChangesAValue) {
  const BikeParams p = Bx15({"drive.gear_ratio=3.4", " battery.power_max_w = 1.5e5 "});
  EXPECT_EQ(p.drive.gamma_c, 3.4);
  EXPECT_EQ(p.battery.power_max, 1.5e5);
  const BikeParams q = Bx15();
  EXPECT_EQ(q.drive.gamma_c, 2.8);
}

TEST(BikeTest, LaterOverrideWins) {
  const BikeParams p = Bx15({"drive.gear_ratio=3.0", "drive.gear_ratio=3.3"});
  EXPECT_EQ(p.drive.gamma_c, 3.3);
}

TEST(BikeTest, OverrideReplacesABadFileValue) {
  int line = 0;
  const std::string text = Bx15WithValue("controller.efficiency", "1.2", &line);
  const BikeParams p = ParseBike(text, kName, {"controller.efficiency=0.9"});
  EXPECT_EQ(p.controller.eta_mc, 0.9);
}

TEST(BikeTest, OverrideSuppliesAMissingKey) {
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  lines.erase(lines.begin() + KeyIndex(lines, "limits.border_margin_m"));
  const BikeParams p = ParseBike(Text(lines), kName, {"limits.border_margin_m=0.25"});
  EXPECT_EQ(p.limits.border_margin, 0.25);
}

TEST(BikeTest, BadOverridePathNamesTheOverride) {
  const std::string msg = ErrorOf(BikeToYaml(Bx15()), {"motor.colour=red"});
  EXPECT_CONTAINS(msg, "override 'motor.colour=red'");
  EXPECT_CONTAINS(msg, "unknown key path 'motor.colour'");
  const std::string msg2 = ErrorOf(BikeToYaml(Bx15()), {"gear_ratio=3"});
  EXPECT_CONTAINS(msg2, "unknown key path 'gear_ratio'");
}

TEST(BikeTest, OverrideWithoutEqualsOrValueIsAnError) {
  const std::string no_equals = ErrorOf(BikeToYaml(Bx15()), {"drive.gear_ratio"});
  EXPECT_CONTAINS(no_equals, "override 'drive.gear_ratio': expected section.key=value");
  const std::string no_value = ErrorOf(BikeToYaml(Bx15()), {"drive.gear_ratio="});
  EXPECT_CONTAINS(no_value, "override 'drive.gear_ratio=': missing value");
}

TEST(BikeTest, BadOverrideValueNamesOverrideAndKeyWithoutALine) {
  const std::string msg = ErrorOf(BikeToYaml(Bx15()), {"controller.efficiency=1.2"});
  EXPECT_CONTAINS(msg, "override 'controller.efficiency=1.2': key 'controller.efficiency'");
  EXPECT_CONTAINS(msg, "non-physical value 1.2");
  EXPECT_LACKS(msg, kName + ":");  // the value is not in the file
  const std::string msg2 = ErrorOf(BikeToYaml(Bx15()), {"chassis.base_mass_kg=abc"});
  EXPECT_CONTAINS(msg2, "override 'chassis.base_mass_kg=abc': key 'chassis.base_mass_kg'");
  EXPECT_CONTAINS(msg2, "expected a number, got 'abc'");
  const std::string msg3 = ErrorOf(BikeToYaml(Bx15()), {"motor.count=-1"});
  EXPECT_CONTAINS(msg3, "override 'motor.count=-1': key 'motor.count'");
}

TEST(BikeTest, OverrideBreakingARelationNamesTheOverride) {
  const std::string msg = ErrorOf(BikeToYaml(Bx15()), {"tyre.toroid_radius_m=0.4"});
  EXPECT_CONTAINS(msg, "override 'tyre.toroid_radius_m=0.4': key 'tyre.toroid_radius_m'");
}

TEST(BikeTest, FileErrorsBeforeOverridesStillNameTheFileLine) {
  // An unknown key in the file is reported with its line even when overrides are given.
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int i = KeyIndex(lines, "initial.state_of_charge");
  lines.insert(lines.begin() + i + 1, "  fuel_l: 0");
  const std::string msg = ErrorOf(Text(lines), {"drive.gear_ratio=3"});
  EXPECT_CONTAINS(msg, At(i + 2, "initial.fuel_l"));
}

// ---- LoadBike on files ------------------------------------------------------------------------

TEST(BikeTest, LoadBikeNamesTheFileAndLine) {
  const std::string path = ::testing::TempDir() + "bike_test_bad.yaml";
  int line = 0;
  {
    std::ofstream out(path);
    out << Bx15WithValue("environment.gravity_m_per_s2", "-9.81", &line);
  }
  try {
    LoadBike(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), path + ":" + std::to_string(line) +
                                    ": key 'environment.gravity_m_per_s2'");
  }
  std::remove(path.c_str());
}

TEST(BikeTest, LoadBikeOfAMissingFileIsAnInputError) {
  const std::string path = ::testing::TempDir() + "no_such_bike.yaml";
  try {
    LoadBike(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), path);
    EXPECT_CONTAINS(e.what(), "cannot open");
  }
}

TEST(BikeTest, LoadBikeSyntaxErrorNamesTheFileAndLine) {
  const std::string path = ::testing::TempDir() + "bike_test_syntax.yaml";
  std::vector<std::string> lines = Lines(BikeToYaml(Bx15()));
  const int i = KeyIndex(lines, "drive.efficiency");
  lines[i] = "     efficiency: 0.95";
  {
    std::ofstream out(path);
    out << Text(lines);
  }
  try {
    LoadBike(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), path + ":" + std::to_string(i + 1) + ": YAML syntax error");
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ttz::lap
