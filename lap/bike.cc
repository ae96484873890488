#include "lap/bike.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <sstream>

#include "common/csv.h"
#include "common/error.h"
#include "common/parse_number.h"

namespace ttz::lap {

// ---- Derived figures ------------------------------------------------------------------------

PackFigures Pack(const BikeParams& p) {
  const BatteryParams& b = p.battery;
  PackFigures f;
  f.V_bn1 = b.cells_series * b.cell_ocv_full;
  f.V_bn0 = b.cells_series * b.cell_ocv_empty;
  f.R_b = b.cells_series * b.cell_resistance / b.cells_parallel;
  f.e_i = static_cast<double>(b.cells_series) * b.cells_parallel * b.cell_energy;
  f.mass = f.e_i / b.energy_density;
  return f;
}

double TotalMass(const BikeParams& p) {
  return p.chassis.base_mass + p.motor.count * p.motor.mass + Pack(p).mass;
}

EquivalentMotor MotorsInParallel(const BikeParams& p) {
  const MotorParams& m = p.motor;
  const double n = m.count;
  EquivalentMotor e;
  e.R_m0 = m.R_m0 / n;
  e.sigma_R = m.sigma_R / n;
  e.k_V0 = m.k_V0;
  e.k_tau0 = m.k_tau0;
  e.sigma_m = m.sigma_m;
  e.i_m0 = n * m.i_m0;
  e.current_max = n * m.current_max;
  e.voltage_max = m.voltage_max;
  e.T_0 = m.T_0;
  e.C = n * m.C;
  e.q_0 = n * m.q_0;
  e.q_1 = n * m.q_1;
  e.V_1 = m.V_1;
  return e;
}

double InitialEnergy(const BikeParams& p) { return p.initial.state_of_charge * Pack(p).e_i; }

// ---- The key table --------------------------------------------------------------------------

namespace {

// Allowed values of a key: lo < x (or lo <= x) and x < hi (or x <= hi).
struct Range {
  double lo, hi;
  bool lo_closed, hi_closed;
  bool Contains(double x) const {
    return (lo_closed ? x >= lo : x > lo) && (hi_closed ? x <= hi : x < hi);
  }
  std::string Describe() const {
    std::ostringstream o;
    const bool no_lo = std::isinf(lo), no_hi = std::isinf(hi);
    if (no_lo && no_hi) return "any finite number";
    if (no_hi) {
      o << (lo_closed ? ">= " : "> ") << lo;
      return o.str();
    }
    o << "in " << (lo_closed ? "[" : "(") << lo << ", " << hi << (hi_closed ? "]" : ")");
    return o.str();
  }
};
constexpr double kInf = HUGE_VAL;
const Range kPositive{0.0, kInf, false, false};
const Range kNonNegative{0.0, kInf, true, false};
const Range kAnyFinite{-kInf, kInf, false, false};
const Range kEfficiency{0.0, 1.0, false, true};      // (0, 1]
const Range kCelsius{-273.15, kInf, false, false};   // above absolute zero
const Range kAtLeastOne{1.0, kInf, true, false};     // integers >= 1

struct KeySpec {
  const char* section;
  const char* key;
  double* (*real)(BikeParams&);  // exactly one of real / integer is set
  int* (*integer)(BikeParams&);
  Range range;
  const char* doc;  // unit and meaning, written as a comment by BikeToYaml
  std::string Path() const { return std::string(section) + "." + key; }
};

#define TTZ_REAL(sec, key, member, range, doc) \
  KeySpec{sec, key, [](BikeParams& p) -> double* { return &p.member; }, nullptr, range, doc}
#define TTZ_INT(sec, key, member, range, doc) \
  KeySpec{sec, key, nullptr, [](BikeParams& p) -> int* { return &p.member; }, range, doc}

const std::vector<KeySpec>& Keys() {
  static const std::vector<KeySpec> keys = {
      TTZ_REAL("chassis", "base_mass_kg", chassis.base_mass, kPositive,
               "bike + rider without motors and pack [kg]; total mass is derived"),
      TTZ_REAL("chassis", "cog_height_m", chassis.h, kPositive, "h, centre-of-mass height [m]"),
      TTZ_REAL("chassis", "roll_inertia_kg_m2", chassis.I_xx, kPositive, "I_xx [kg m^2]"),
      TTZ_REAL("chassis", "pitch_inertia_kg_m2", chassis.I_yy, kNonNegative, "I_yy [kg m^2]"),
      TTZ_REAL("chassis", "yaw_inertia_kg_m2", chassis.I_zz, kNonNegative, "I_zz [kg m^2]"),
      TTZ_REAL("chassis", "gyroscopic_inertia_kg_m2", chassis.I_gy, kNonNegative,
               "I_gy = 2 I_wy + gamma_c I_ey [kg m^2]"),
      TTZ_REAL("chassis", "wheel_spin_inertia_kg_m2", chassis.I_wy, kPositive, "I_wy [kg m^2]"),

      TTZ_REAL("tyre", "wheel_radius_m", tyre.r, kPositive, "r [m]"),
      TTZ_REAL("tyre", "toroid_radius_m", tyre.r_t, kNonNegative, "r_t [m]"),
      TTZ_REAL("tyre", "longitudinal_slip_stiffness", tyre.K_kappa, kPositive, "K_kappa [1]"),
      TTZ_REAL("tyre", "sideslip_stiffness_per_rad", tyre.K_beta, kPositive, "K_beta [1/rad]"),
      TTZ_REAL("tyre", "roll_stiffness_per_rad", tyre.K_phi, kNonNegative, "K_phi [1/rad]"),
      TTZ_REAL("tyre", "radial_stiffness_n_per_m", tyre.K_s, kPositive, "K_s [N/m]"),
      TTZ_REAL("tyre", "radial_damping_n_s_per_m", tyre.K_c, kNonNegative, "K_c [N s/m]"),
      TTZ_REAL("tyre", "longitudinal_adherence", tyre.mu_x, kPositive, "mu_x [1]"),
      TTZ_REAL("tyre", "lateral_adherence", tyre.mu_y, kPositive, "mu_y [1]"),
      TTZ_REAL("tyre", "rolling_resistance_coefficient", tyre.mu_r, kNonNegative, "mu_r [1]"),

      TTZ_REAL("aero", "air_density_kg_per_m3", aero.rho, kPositive, "rho [kg/m^3]"),
      TTZ_REAL("aero", "drag_area_m2", aero.C_d, kNonNegative, "C_d (times frontal area) [m^2]"),
      TTZ_REAL("aero", "lift_area_m2", aero.C_l, kAnyFinite,
               "C_l (times frontal area) [m^2], lift positive up"),

      TTZ_INT("motor", "count", motor.count, kAtLeastOne, "motors in parallel [1]"),
      TTZ_REAL("motor", "mass_kg", motor.mass, kPositive, "mass of one motor [kg]"),
      TTZ_REAL("motor", "resistance_ohm", motor.R_m0, kPositive, "R_m0, one motor, at T_0 [ohm]"),
      TTZ_REAL("motor", "resistance_temperature_coefficient_ohm_per_k", motor.sigma_R,
               kNonNegative, "sigma_R, one motor [ohm/K]"),
      TTZ_REAL("motor", "back_emf_constant_v_s_per_rad", motor.k_V0, kPositive,
               "k_V0 at T_0 [V s/rad]"),
      TTZ_REAL("motor", "torque_constant_n_m_per_a", motor.k_tau0, kPositive,
               "k_tau0 at T_0 [N m/A], <= k_V0"),
      TTZ_REAL("motor", "constant_temperature_coefficient_v_s_per_rad_k", motor.sigma_m,
               kNonNegative, "sigma_m = -dk/dT [V s/(rad K)]"),
      TTZ_REAL("motor", "current_offset_a", motor.i_m0, kNonNegative, "i_m0, one motor [A]"),
      TTZ_REAL("motor", "current_max_a", motor.current_max, kPositive, "limit of one motor [A]"),
      TTZ_REAL("motor", "voltage_max_v", motor.voltage_max, kPositive, "V_max [V]"),
      TTZ_REAL("motor", "reference_temperature_c", motor.T_0, kCelsius, "T_0 [degC]"),
      TTZ_REAL("motor", "thermal_capacity_j_per_k", motor.C, kPositive, "C, one motor [J/K]"),
      TTZ_REAL("motor", "heat_conduction_standstill_w_per_k", motor.q_0, kNonNegative,
               "q_0, one motor [W/K]"),
      TTZ_REAL("motor", "heat_conduction_at_v1_w_per_k", motor.q_1, kNonNegative,
               "q_1, one motor [W/K]"),
      TTZ_REAL("motor", "heat_conduction_speed_v1_m_per_s", motor.V_1, kPositive, "V_1 [m/s]"),

      TTZ_REAL("controller", "efficiency", controller.eta_mc, kEfficiency, "eta_mc [1]"),

      TTZ_INT("battery", "cells_series", battery.cells_series, kAtLeastOne, "[1]"),
      TTZ_INT("battery", "cells_parallel", battery.cells_parallel, kAtLeastOne, "[1]"),
      TTZ_REAL("battery", "cell_ocv_full_v", battery.cell_ocv_full, kPositive, "[V]"),
      TTZ_REAL("battery", "cell_ocv_empty_v", battery.cell_ocv_empty, kPositive,
               "[V], < cell_ocv_full_v"),
      TTZ_REAL("battery", "cell_resistance_ohm", battery.cell_resistance, kNonNegative, "[ohm]"),
      TTZ_REAL("battery", "cell_energy_j", battery.cell_energy, kPositive, "[J]"),
      TTZ_REAL("battery", "energy_density_j_per_kg", battery.energy_density, kPositive,
               "pack energy / pack mass [J/kg]"),
      TTZ_REAL("battery", "power_max_w", battery.power_max, kPositive, "P_b^max on V_bn i_b [W]"),

      TTZ_REAL("drive", "gear_ratio", drive.gamma_c, kPositive, "gamma_c = omega_m / omega_w [1]"),
      TTZ_REAL("drive", "efficiency", drive.eta_c, kEfficiency, "eta_c [1]"),

      TTZ_REAL("initial", "speed_m_per_s", initial.V, kPositive, "V(0) [m/s]"),
      TTZ_REAL("initial", "motor_temperature_c", initial.T, kCelsius, "T(0) [degC]"),
      TTZ_REAL("initial", "state_of_charge", initial.state_of_charge, kEfficiency,
               "e(0) / e_i [1]"),

      TTZ_REAL("environment", "gravity_m_per_s2", environment.g, kPositive, "g [m/s^2]"),
      TTZ_REAL("environment", "ambient_temperature_c", environment.T_ext, kCelsius,
               "T_ext [degC]"),

      TTZ_REAL("limits", "roll_rate_max_rad_per_s", limits.omega_phi_max, kPositive,
               "omega_phi^max [rad/s]"),
      TTZ_REAL("limits", "yaw_rate_max_rad_per_s", limits.Omega_z_max, kPositive,
               "Omega_z^max [rad/s]"),
      TTZ_REAL("limits", "border_margin_m", limits.border_margin, kNonNegative,
               "contact point kept this far inside each border [m]"),
      TTZ_REAL("limits", "brake_torque_max_n_m", limits.brake_torque_max, kPositive,
               "largest brake torque at the wheel [N m] (bounds the state tau_w)"),
      TTZ_REAL("limits", "yaw_acceleration_weight_s4_per_rad2", limits.yaw_accel_weight, kPositive,
               "c_y [s^4/rad^2], cost of the yaw acceleration: lap time + c_y int (dOmega_z/dt)^2 dt"),
      TTZ_REAL("limits", "torque_rate_weight_s3_per_n2_m2", limits.torque_rate_weight, kPositive,
               "c_t [s^3/(N m)^2], cost of the torque rate: lap time + c_t int (dtau_w/dt)^2 dt"),
      TTZ_REAL("limits", "roll_rate_weight_s2_per_rad2", limits.roll_rate_weight, kNonNegative,
               "c_r [s^2/rad^2], cost of the roll rate: lap time + c_r int omega_phi^2 dt"),
  };
  return keys;
}

#undef TTZ_REAL
#undef TTZ_INT

std::vector<std::string> SectionNames() {
  std::vector<std::string> names;
  for (const KeySpec& k : Keys())
    if (names.empty() || names.back() != k.section) names.push_back(k.section);
  return names;
}

const KeySpec* FindKey(const std::string& path) {
  for (const KeySpec& k : Keys())
    if (k.Path() == path) return &k;
  return nullptr;
}

std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// Where a key's value came from: a line of the file or an override.
class Locator {
 public:
  explicit Locator(std::string file) : file_(std::move(file)) {}
  void MarkOverride(const std::string& path, const std::string& text) { overrides_[path] = text; }
  // "<file>:<line>: key 'path'" or "override 'path=value': key 'path'".
  std::string At(const std::string& path, const YAML::Node& node) const {
    const auto o = overrides_.find(path);
    if (o != overrides_.end()) return "override '" + o->second + "': key '" + path + "'";
    return AtLine(path, node.IsDefined() ? node.Mark().line + 1 : 0);
  }
  std::string AtLine(const std::string& path, long line) const {
    return Where(file_, line) + ": key '" + path + "'";
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::map<std::string, std::string> overrides_;
};

// Rejects keys that are not in the table and keys given twice, with their line.
void CheckKnownKeys(const YAML::Node& root, const Locator& loc) {
  const std::vector<std::string> sections = SectionNames();
  std::set<std::string> seen_sections;
  for (const auto& s : root) {
    const long line = s.first.Mark().line + 1;
    if (!s.first.IsScalar()) throw InputError(Where(loc.file(), line), "expected a section name");
    const std::string name = s.first.as<std::string>();
    if (std::find(sections.begin(), sections.end(), name) == sections.end())
      throw InputError(loc.AtLine(name, line),
                       "unknown section (known sections: " + Join(sections) + ")");
    if (!seen_sections.insert(name).second)
      throw InputError(loc.AtLine(name, line), "section given twice");
    if (!s.second.IsMap())
      throw InputError(loc.AtLine(name, line), "expected a map of keys under section '" + name + "'");
    std::set<std::string> seen;
    for (const auto& k : s.second) {
      const long kline = k.first.Mark().line + 1;
      if (!k.first.IsScalar())
        throw InputError(Where(loc.file(), kline), "expected a key name in section '" + name + "'");
      const std::string path = name + "." + k.first.as<std::string>();
      if (!FindKey(path)) {
        std::vector<std::string> known;
        for (const KeySpec& spec : Keys())
          if (name == spec.section) known.push_back(spec.key);
        throw InputError(loc.AtLine(path, kline),
                         "unknown key (keys of section '" + name + "': " + Join(known) + ")");
      }
      if (!seen.insert(path).second) throw InputError(loc.AtLine(path, kline), "key given twice");
    }
  }
}

// Applies "section.key=value" overrides to the YAML tree.
void ApplyOverrides(YAML::Node& root, const std::vector<std::string>& overrides, Locator& loc) {
  for (const std::string& text : overrides) {
    const auto eq = text.find('=');
    if (eq == std::string::npos)
      throw InputError("override '" + text + "'", "expected section.key=value");
    const std::string path = TrimSpace(text.substr(0, eq));
    const std::string value = TrimSpace(text.substr(eq + 1));
    const KeySpec* spec = FindKey(path);
    if (!spec)
      throw InputError("override '" + text + "'",
                       "unknown key path '" + path + "' (known: " + Join(BikeKeys()) + ")");
    if (value.empty()) throw InputError("override '" + text + "'", "missing value");
    const YAML::Node& const_root = root;  // const access does not insert keys
    if (const_root[spec->section].IsDefined() && !const_root[spec->section].IsMap())
      throw InputError("override '" + text + "'", "section '" + std::string(spec->section) +
                                                      "' of the file is not a map");
    root[spec->section][spec->key] = value;
    loc.MarkOverride(path, text);
  }
}

double ReadReal(const YAML::Node& node, const std::string& where) {
  if (!node.IsScalar()) throw InputError(where, "expected a number");
  double x;
  try {
    x = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(where, "expected a number, got '" + node.Scalar() + "'");
  }
  if (!std::isfinite(x)) throw InputError(where, "expected a finite number, got '" + node.Scalar() + "'");
  return x;
}

int ReadInteger(const YAML::Node& node, const std::string& where) {
  if (!node.IsScalar()) throw InputError(where, "expected an integer");
  const std::string& s = node.Scalar();
  const std::optional<int> v = ParseInt(s);
  if (!v || *v > 1000000 || *v < -1000000) throw InputError(where, "expected an integer, got '" + s + "'");
  return *v;
}

// The 1-based line of `key` in a section map (yaml-cpp marks an empty value at the next token).
long KeyLine(const YAML::Node& section, const std::string& key) {
  for (const auto& k : section)
    if (k.first.IsScalar() && k.first.Scalar() == key) return k.first.Mark().line + 1;
  return section.Mark().line + 1;
}

// Reads every key of the table into p, checking presence, type and range.
void ReadKeys(const YAML::Node& root, const Locator& loc, BikeParams* p) {
  for (const KeySpec& spec : Keys()) {
    const std::string path = spec.Path();
    const YAML::Node section = root[spec.section];
    if (!section.IsDefined())
      throw InputError(loc.AtLine(path, 0), "missing key (the file has no section '" +
                                                std::string(spec.section) + "')");
    const YAML::Node node = section[spec.key];
    if (!node.IsDefined() || node.IsNull()) {
      const long line = node.IsDefined() ? KeyLine(section, spec.key) : KeyLine(root, spec.section);
      throw InputError(loc.AtLine(path, line),
                       node.IsDefined() ? "missing value" : "missing key in section '" +
                                                                std::string(spec.section) + "'");
    }
    const std::string where = loc.At(path, node);
    const double value = spec.real ? ReadReal(node, where) : ReadInteger(node, where);
    if (!spec.range.Contains(value)) {
      std::ostringstream o;
      o << "non-physical value " << node.Scalar() << ": allowed range " << spec.range.Describe();
      throw InputError(where, o.str());
    }
    if (spec.real)
      *spec.real(*p) = value;
    else
      *spec.integer(*p) = static_cast<int>(value);
  }
}

// Relations between keys; the error names the key docs/bike.md marks for each.
void CheckRelations(const YAML::Node& root, const Locator& loc, const BikeParams& p) {
  auto fail = [&](const char* section, const char* key, const std::string& what) {
    const std::string path = std::string(section) + "." + key;
    throw InputError(loc.At(path, root[section][key]), what);
  };
  if (!(p.tyre.r_t < p.tyre.r))
    fail("tyre", "toroid_radius_m", "must be smaller than tyre.wheel_radius_m (r_t < r)");
  if (!(p.tyre.r_t < p.chassis.h))
    fail("chassis", "cog_height_m", "must exceed tyre.toroid_radius_m (h > r_t)");
  if (!(p.battery.cell_ocv_empty < p.battery.cell_ocv_full))
    fail("battery", "cell_ocv_empty_v", "must be below battery.cell_ocv_full_v");
  if (!(p.motor.k_tau0 <= p.motor.k_V0))
    fail("motor", "torque_constant_n_m_per_a",
         "must not exceed motor.back_emf_constant_v_s_per_rad (k_tau <= k_V, paper section 2.3)");
}

// Shortest decimal text that reads back as exactly x.
std::string ExactText(double x) {
  char buf[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

BikeParams ParseTree(YAML::Node root, const std::string& name,
                     const std::vector<std::string>& overrides) {
  Locator loc(name);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw InputError(Where(name, root.Mark().line + 1), "expected a map of sections");
  CheckKnownKeys(root, loc);  // the file's own keys, with their lines
  ApplyOverrides(root, overrides, loc);
  BikeParams p{};
  ReadKeys(root, loc, &p);
  CheckRelations(root, loc, p);
  return p;
}

}  // namespace

std::vector<std::string> BikeKeys() {
  std::vector<std::string> paths;
  for (const KeySpec& k : Keys()) paths.push_back(k.Path());
  return paths;
}

std::vector<std::string> RealBikeKeys() {
  std::vector<std::string> paths;
  for (const KeySpec& k : Keys())
    if (k.real) paths.push_back(k.Path());
  return paths;
}

double& RealBikeValue(BikeParams& p, const std::string& path) {
  const KeySpec* spec = FindKey(path);
  if (!spec || !spec->real) throw std::invalid_argument("not a real-valued bike key: '" + path + "'");
  return *spec->real(p);
}

BikeParams ParseBike(const std::string& yaml_text, const std::string& name,
                     const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(name, e.mark.line + 1), "YAML syntax error: " + e.msg);
  }
  return ParseTree(root, name, overrides);
}

BikeParams LoadBike(const std::string& yaml_path, const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    throw InputError(yaml_path, "cannot open the file");
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(yaml_path, e.mark.line + 1), "YAML syntax error: " + e.msg);
  }
  return ParseTree(root, yaml_path, overrides);
}

std::string BikeToYaml(const BikeParams& params) {
  BikeParams p = params;  // the accessors take a non-const reference
  std::ostringstream o;
  o << "# bike.yaml (ttz lap): SI units, temperatures in degC; see docs/bike.md.\n";
  const PackFigures pack = Pack(p);
  o << "# derived: total mass " << ExactText(TotalMass(p)) << " kg, pack mass "
    << ExactText(pack.mass) << " kg, pack energy " << ExactText(pack.e_i) << " J, V_bn1 "
    << ExactText(pack.V_bn1) << " V, V_bn0 " << ExactText(pack.V_bn0) << " V, R_b "
    << ExactText(pack.R_b) << " ohm\n";
  std::string section;
  for (const KeySpec& k : Keys()) {
    if (section != k.section) {
      section = k.section;
      o << section << ":\n";
    }
    const std::string value =
        k.real ? ExactText(*k.real(p)) : std::to_string(*k.integer(p));
    o << "  " << k.key << ": " << value << "  # " << k.doc << "\n";
  }
  return o.str();
}

}  // namespace ttz::lap
