#include "lap/lap_artefact.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include "common/artefact.h"
#include "common/error.h"
#include "lap/lap_report.h"
#include "lap/solver/hamiltonian.h"

namespace ttz::lap {
namespace {

// The shortest mesh interval [m].
double MinSpacing(const std::vector<double>& s) {
  double h = s.back() - s.front();
  for (size_t k = 0; k + 1 < s.size(); ++k) h = std::min(h, s[k + 1] - s[k]);
  return h;
}

// Units of the costates of the physical states: dt/dx_i along the lap, [s / unit of x_i].
constexpr std::array<const char*, kNumStates> kCostateUnits = {
    "s/m", "s/rad", "s^2/m", "s/rad", "s/m", "s/rad", "s^2/rad", "s/K", "s/J", "s^2/rad", "s^2/m",
    "s^2/rad", "s/(N m)"};

struct ChannelSpec {
  const char* name;
  std::vector<double> LapChannels::*member;
  const char* units;
  const char* description;
};

const ChannelSpec kChannels[] = {
    {"sdot", &LapChannels::sdot, "m/s", "ds/dt, speed along the centre line (eq. 10a)"},
    {"accel/long", &LapChannels::accel_long, "m/s^2", "longitudinal acceleration dV/dt"},
    {"accel/lat", &LapChannels::accel_lat, "m/s^2",
     "lateral acceleration V Omega_z, right positive (centripetal, exact in steady cornering)"},
    {"tyre/load", &LapChannels::tyre_load, "N", "tyre load N (eq. 18)"},
    {"tyre/force_x", &LapChannels::tyre_force_x, "N", "longitudinal tyre force F_x, forward positive (eq. 18)"},
    {"tyre/force_y", &LapChannels::tyre_force_y, "N", "lateral tyre force F_y, right positive (eq. 18)"},
    {"tyre/ellipse", &LapChannels::ellipse_usage, "1",
     "adherence ellipse usage (F_x/(N mu_x))^2 + (F_y/(N mu_y))^2, at most 1 (eq. 19)"},
    {"tyre/slip", &LapChannels::tyre_slip, "1", "longitudinal slip kappa_w (eq. 20)"},
    {"aero/drag", &LapChannels::aero_drag, "N", "aerodynamic drag D (eq. 21)"},
    {"motor/torque", &LapChannels::motor_torque, "N m", "shaft torque of all motors tau_e = k_tau (i_m - i_m0) (eq. 25, 31)"},
    {"motor/speed", &LapChannels::motor_speed, "rad/s", "motor speed gamma_c omega_w"},
    {"motor/current", &LapChannels::motor_current, "A", "current of all motors i_m (eq. 25)"},
    {"motor/voltage", &LapChannels::motor_voltage, "V", "motor voltage V_mm (eq. 24, 30)"},
    {"motor/power", &LapChannels::motor_power, "W", "electric power into the motors V_mm i_m"},
    {"wheel/power", &LapChannels::wheel_power, "W", "power of the drive at the wheel tau_t omega_w; negative while the current is cut (motor friction)"},
    {"battery/current", &LapChannels::battery_current, "A", "pack current i_b (eq. 32)"},
    {"battery/voltage", &LapChannels::battery_voltage, "V", "pack terminal voltage V_mb = V_bn - R_b i_b (eq. 22a)"},
    {"battery/ocv", &LapChannels::battery_ocv, "V", "pack open-circuit voltage V_bn (eq. 22b)"},
    {"battery/power", &LapChannels::battery_power, "W",
     "power drawn from the pack's energy V_bn i_b = -de/dt (eq. 33), internal losses included"},
    {"energy_used", &LapChannels::energy_used, "J", "pack energy used since the start e(0) - e"},
    {"efficiency/motor", &LapChannels::efficiency_motor, "1",
     "motor efficiency omega_m tau_e / (V_mm i_m); NaN where the motors take under 0.1 % of P_b^max"},
    {"efficiency/electrical", &LapChannels::efficiency_electrical, "1",
     "controller and pack efficiency V_mm i_m / (V_bn i_b); NaN where the pack gives under 0.1 % of P_b^max"},
    {"efficiency/powertrain", &LapChannels::efficiency_powertrain, "1",
     "power-train efficiency, wheel/power / battery/power; NaN where the pack gives under 0.1 % of P_b^max"},
};

// Component i of each row, times `scale`.
template <size_t N>
std::vector<double> Column(const std::vector<std::array<double, N>>& rows, size_t i, double scale = 1.0) {
  std::vector<double> c(rows.size());
  for (size_t k = 0; k < rows.size(); ++k) c[k] = rows[k][i] * scale;
  return c;
}

// The interval midpoints of a mesh [m].
std::vector<double> Midpoints(const std::vector<double>& s) {
  std::vector<double> mid(s.size() - 1);
  for (size_t k = 0; k + 1 < s.size(); ++k) mid[k] = 0.5 * (s[k] + s[k + 1]);
  return mid;
}

void WriteAlongS(ArtefactWriter& w, const Vehicle& v, const LapSolution& sol, const LapChannels& ch) {
  w.WriteVector("s", sol.s, "m", "arc length of the centre line at the mesh nodes, 0 at the start");
  w.WriteVector("t", sol.t, "s", "time since the start");
  const Scales sc = DefaultScales(v);
  for (int i = 0; i < kNumStates; ++i) {
    const std::string name = kStateNames[i];
    w.WriteVector("state/" + name, Column(sol.x, i), kStateUnits[i], "state " + name + " (lap/model/state.h)");
    w.WriteVector("costate/" + name, Column(sol.lambda, i, 1.0 / sc.state[i]), kCostateUnits[i],
                  "costate of " + name + ": sensitivity of the remaining lap time to " + name);
  }
  for (int i = 0; i < kNumControls; ++i) {
    const std::string name = kControlNames[i];
    w.WriteVector("control/" + name, Column(sol.u, i), kControlUnits[i],
                  "control " + name + " (lap/model/state.h): the mean of the neighbouring intervals'");
    w.WriteVector("control_interval/" + name, Column(sol.u_interval, i), kControlUnits[i],
                  "control " + name + " of each mesh interval, as the transcription holds it");
  }
  for (const ChannelSpec& c : kChannels) w.WriteVector(c.name, ch.*c.member, c.units, c.description);
  for (int j = 0; j < kNumConstraints; ++j)
    w.WriteVector(std::string("constraint/") + kConstraintNames[j], ch.constraint[j], "1",
                  "constraint value g <= 0 scaled by its limit (lap/model/constraints.h); 0 is active");
}

void WriteQss(ArtefactWriter& w, const QssLap& qss) {
  w.WriteVector("qss/s", qss.s, "m", "arc length of the quasi-steady-state lap's nodes");
  w.WriteVector("qss/V", qss.V, "m/s", "speed of the quasi-steady-state lap on the centre line");
  w.WriteVector("qss/t", qss.t, "s", "time of the quasi-steady-state lap");
}

void WriteContinuation(ArtefactWriter& w, const SolveSummary& summary) {
  std::vector<double> eps, lap_time, seconds;
  std::vector<int64_t> iterations, converged;
  for (const ContinuationStep& c : summary.steps) {
    eps.push_back(c.eps);
    lap_time.push_back(c.lap_time);
    seconds.push_back(c.seconds);
    iterations.push_back(c.iterations);
    converged.push_back(c.converged ? 1 : 0);
  }
  w.WriteVector("continuation/eps", eps, "1", "barrier weight of each continuation step");
  w.WriteVector("continuation/lap_time", lap_time, "s", "lap time at the end of each step (0 if invalid)");
  w.WriteVector("continuation/seconds", seconds, "s", "wall time of each step");
  w.WriteIntVector("continuation/iterations", iterations, "1", "optimiser iterations of each step");
  w.WriteIntVector("continuation/converged", converged, "1", "1 if the step converged, 0 if it was rejected");
}

void WriteAttributes(ArtefactWriter& w, const LapSolution& sol, const SolveSummary& summary,
                     const LapChannels& ch, const QssLap& qss, const LapProvenance& p) {
  w.WriteAttribute("lap_time", sol.lap_time);
  w.WriteAttribute("lap_time_extrapolated", sol.lap_time_extrapolated);
  w.WriteAttribute("eps", sol.eps);
  w.WriteAttribute("qss_lap_time", qss.lap_time);
  w.WriteAttribute("energy_used", ch.figures.energy_used);
  w.WriteAttribute("energy_fraction", ch.figures.energy_fraction);
  w.WriteAttribute("top_speed", ch.figures.top_speed);
  w.WriteAttribute("average_speed", ch.figures.average_speed);
  w.WriteBoolAttribute("converged", summary.converged);
  w.WriteAttribute("message", SolveMessage(summary));
  w.WriteAttribute("max_residual", summary.max_residual);
  w.WriteAttribute("max_state_defect", summary.max_state_defect);
  for (int j = 0; j < kNumConstraints; ++j) {
    w.WriteAttribute(std::string("max_violation_") + kConstraintNames[j],
                     *std::max_element(ch.constraint[j].begin(), ch.constraint[j].end()));
    w.WriteAttribute(std::string("solver_max_violation_") + kConstraintNames[j],
                     summary.max_violation[j]);
  }
  w.WriteAttribute("control_failures", static_cast<int64_t>(summary.control_failures));
  w.WriteAttribute("iterations", static_cast<int64_t>(summary.iterations));
  w.WriteAttribute("solve_seconds", summary.solve_seconds);
  w.WriteAttribute("mesh_ds", p.mesh.ds_m);
  w.WriteAttribute("mesh_dt_max", p.mesh.dt_max_s);
  w.WriteAttribute("mesh_ds_min", MinSpacing(sol.s));
  w.WriteAttribute("nodes", static_cast<int64_t>(sol.s.size()));
  w.WriteAttribute("solver", p.solver);
  w.WriteAttribute("max_iterations", static_cast<int64_t>(p.solver_options.max_iterations));
  w.WriteAttribute("mu_globalization", p.solver_options.mu_globalization);
  w.WriteAttribute("mu_strategy", p.solver_options.mu_strategy);
  w.WriteAttribute("mu_init", p.solver_options.mu_init);
  w.WriteAttribute("window_m", p.solver_options.window_m);
  w.WriteAttribute("window_overlap_m", p.solver_options.window_overlap_m);
  w.WriteAttribute("window_eps_end", p.solver_options.window_eps_end);
  w.WriteAttribute("window_charge_price", p.solver_options.window_charge_price_s_per_j);
  w.WriteBoolAttribute("first_step_in_windows", summary.first_step_in_windows);
  w.WriteAttribute("bike_yaml", p.bike_yaml);
  w.WriteAttribute("road_file", p.road_file);
  w.WriteAttribute("road_sha256", p.road_sha256);
  w.WriteAttribute("road_length", p.road_length);
  w.WriteAttribute("init_file", p.init_file);
  w.WriteBoolAttribute("mesh_from_init", p.mesh_from_init);
  w.WriteAttribute("guess", p.guess);
  w.WriteAttribute("guess_lap_time", p.guess_lap_time);
  w.WriteAttribute("start", p.start);
  w.WriteAttribute("tool_version", TTZ_VERSION);
}

// The re-simulation check (lap/resimulate.h): its summary as attributes, the scaled difference
// of each state at each node as datasets.
void WriteResim(ArtefactWriter& w, const ResimReport& r, size_t nodes) {
  for (int i = 0; i < kNumStates; ++i) {
    const std::string name = kStateNames[i];
    std::vector<double> d(nodes, std::numeric_limits<double>::quiet_NaN());
    if (r.state_difference.size() == nodes) d = Column(r.state_difference, i);
    w.WriteVector("resim/" + name, d, "1",
                  "re-simulated " + name + " minus the solution's, absolute, over resim_scale_" + name +
                      " (0 at s = 0, NaN where not reached)");
    w.WriteAttribute("resim_scale_" + name, r.scale[i]);
  }
  w.WriteAttribute("resim_lap_time", r.lap_time);
  w.WriteAttribute("resim_lap_time_difference", r.lap_time_difference);
  w.WriteAttribute("resim_lap_time_relative", r.lap_time_relative);
  w.WriteAttribute("resim_max_state_difference", r.max_state_difference_all);
  for (int i = 0; i < kNumStates; ++i)
    w.WriteAttribute(std::string("resim_max_state_difference_") + kStateNames[i], r.max_state_difference[i]);
  w.WriteAttribute("resim_worst_state", kStateNames[r.worst_state]);
  w.WriteAttribute("resim_worst_s", r.worst_s);
  w.WriteBoolAttribute("resim_passed", r.passed);
  w.WriteAttribute("resim_message", r.message);
}

void WriteSensitivities(ArtefactWriter& w, const std::vector<DesignSensitivity>& sensitivities) {
  std::vector<std::string> key, kind;
  std::vector<double> value, per_unit, per_percent;
  for (const DesignSensitivity& d : sensitivities) {
    key.push_back(d.key);
    kind.push_back(d.kind);
    value.push_back(d.value);
    per_unit.push_back(d.per_unit);
    per_percent.push_back(d.per_percent);
  }
  w.WriteStringVector("sensitivity/key", key, "bike.yaml key path of each row (its unit is in its name)");
  w.WriteStringVector("sensitivity/kind", kind,
                      "design, rider, condition or reference: what kind of change the row is (lap/sensitivity.h)");
  w.WriteVector("sensitivity/value", value, "key's", "the key's value in this lap's bike");
  w.WriteVector("sensitivity/per_unit", per_unit, "s per key's unit",
                "dJ/d(value) by the adjoint, J the lap time with the barriers' and the effort's share, on this "
                "mesh at this eps (lap/sensitivity.h)");
  w.WriteVector("sensitivity/per_percent", per_percent, "s",
                "the lap time 1 % more of the value costs: per_unit * value / 100 (degC values in kelvin)");
}

// Reads the rows of a group ("state", "costate", "control": n = the nodes; "control_interval":
// n = the intervals) into `rows`; `per` names what there is one row per, for the message.
template <size_t N>
void ReadRows(const ArtefactReader& r, const std::string& group, const std::array<const char*, N>& names,
              const std::array<const char*, N>& units, size_t n, const char* per,
              std::vector<std::array<double, N>>* rows) {
  rows->assign(n, {});
  for (size_t i = 0; i < N; ++i) {
    const std::string name = group + "/" + names[i];
    const std::vector<double> c = r.ReadVector(name, units[i]);
    if (c.size() != n)
      throw InputError(r.path(), "dataset '" + name + "' has " + std::to_string(c.size()) + " values, " +
                                     std::to_string(n) + " expected (one per " + per + " of 's')");
    for (size_t k = 0; k < n; ++k) (*rows)[k][i] = c[k];
  }
}

// Linear interpolation of rows given at `s` onto `at` (clamped to s's range; one row: that row).
template <size_t N>
std::array<double, N> Interpolate(const std::vector<double>& s, const std::vector<std::array<double, N>>& rows,
                                  double at) {
  if (rows.size() == 1) return rows.front();
  const size_t hi = std::clamp<size_t>(std::upper_bound(s.begin(), s.end(), at) - s.begin(), 1, s.size() - 1);
  const double w = std::clamp((at - s[hi - 1]) / (s[hi] - s[hi - 1]), 0.0, 1.0);
  std::array<double, N> out;
  for (size_t i = 0; i < N; ++i) out[i] = (1.0 - w) * rows[hi - 1][i] + w * rows[hi][i];
  return out;
}

}  // namespace

void WriteLap(const std::string& path, const Vehicle& v, const LapSolution& sol,
              const SolveSummary& summary, const LapChannels& channels, const QssLap& qss,
              const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities,
              const LapProvenance& provenance) {
  ArtefactWriter w(path, kLapSchema, kLapSchemaVersion);
  WriteAlongS(w, v, sol, channels);
  WriteQss(w, qss);
  WriteContinuation(w, summary);
  WriteAttributes(w, sol, summary, channels, qss, provenance);
  WriteResim(w, resim, sol.s.size());
  if (!sensitivities.empty()) WriteSensitivities(w, sensitivities);
  w.Commit();
}

WarmStart ReadLapForWarmStart(const std::string& path) {
  const ArtefactReader r(path, kLapSchema, kLapSchemaVersion, kLapOldestWarmStartVersion);
  WarmStart ws;
  ws.s = r.ReadVector("s", "m");
  const size_t n = ws.s.size();
  if (n < 2) throw InputError(path, "dataset 's' has " + std::to_string(n) + " values, at least 2 expected");
  for (size_t k = 1; k < n; ++k)
    if (!(ws.s[k] > ws.s[k - 1]))
      throw InputError(path, "dataset 's' is not strictly increasing at index " + std::to_string(k));
  ReadRows(r, "state", kStateNames, kStateUnits, n, "node", &ws.x);
  ReadRows(r, "costate", kStateNames, kCostateUnits, n, "node", &ws.lambda);
  ReadRows(r, "control", kControlNames, kControlUnits, n, "node", &ws.u);
  if (r.schema_version() >= 3)  // version 2 has no control_interval/*
    ReadRows(r, "control_interval", kControlNames, kControlUnits, n - 1, "interval", &ws.u_interval);
  ws.eps = r.ReadDoubleAttribute("eps");
  ws.mesh.ds_m = r.ReadDoubleAttribute("mesh_ds");
  ws.mesh.dt_max_s = r.ReadDoubleAttribute("mesh_dt_max");
  if (r.HasAttribute("start")) ws.start = r.ReadStringAttribute("start");
  ws.road_sha256 = r.ReadStringAttribute("road_sha256");
  ws.road_length = r.ReadDoubleAttribute("road_length");
  return ws;
}

SolverGuess ResampleWarmStart(const WarmStart& w, const Vehicle& v, const std::vector<double>& mesh) {
  const Scales sc = DefaultScales(v);
  SolverGuess g;
  for (double s : mesh) {
    g.x.push_back(Interpolate(w.s, w.x, s));
    StateVector<double> lambda = Interpolate(w.s, w.lambda, s);
    for (int i = 0; i < kNumStates; ++i) lambda[i] *= sc.state[i];  // H's lambda~_i = S_i lambda_i
    g.lambda.push_back(lambda);
    g.u.push_back(Interpolate(w.s, w.u, s));
  }
  if (w.u_interval.empty()) return g;  // a version 2 file: the solvers start from the node controls
  const std::vector<double> from = Midpoints(w.s);
  for (double s : Midpoints(mesh)) g.u_interval.push_back(Interpolate(from, w.u_interval, s));
  return g;
}

}  // namespace ttz::lap
