// Benchmark of the lap solvers on a piece of a road.h5 (e.g. the Snaefell course that `make run`
// fits): both solvers from the QSS guess (the indirect one on the racing line, Ipopt on the centre line, as
// `lap`; `guess=racing-line|centre-line` sets both) on the mesh of `lap --ds DS_M --dt-max DT_MAX_S` (lap/mesh.h)
// from 0 to LENGTH_M, printing lap time, convergence, iterations, wall time, time per iteration,
// CPU time (all threads) per iteration and node, peak memory and the re-simulation check's
// lap-time and largest state difference, and on a line below each state's largest difference
// and how many nodes exceed 0.1 % (not a test). KEY=VALUE arguments after EPS_START override
// bike.yaml values as `lap --set` does; `indirect.NAME=VALUE` sets the indirect solver's option NAME
// (those of kIndirectKeys below, e.g. `indirect.window_m=3000`; `indirect.homotopy=0|1`),
// `ipopt.NAME=VALUE` Ipopt's option NAME (e.g. `ipopt.print_level=5`). CPU time per iteration and node is the figure to compare across
// meshes: other processes sharing the machine do not count in it.
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/log.h"
#include "common/memory.h"
#include "common/parse_number.h"
#include "common/road_artefact.h"
#include "lap/bike.h"
#include "lap/mesh.h"
#include "lap/qss.h"
#include "lap/resimulate.h"
#include "lap/solver/indirect.h"
#include "lap/solver/ipopt_direct.h"

namespace {

double PeakMegabytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// User + system CPU time of this process, all threads [s].
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The re-simulation check state by state, on a line below the row: each state's largest scaled
// difference [%] and, in brackets, the nodes where it exceeds `tolerance`.
void PrintResimByState(const ttz::lap::ResimReport& r, double tolerance) {
  using namespace ttz::lap;
  std::printf("  re-simulation by state:");
  for (int i = 0; i < kNumStates; ++i) {
    const auto over = std::count_if(r.state_difference.begin(), r.state_difference.end(),
                                    [&](const StateVector<double>& d) { return d[i] > tolerance; });
    std::printf(" %s %.2g %% (%td)", kStateNames[i], 100.0 * r.max_state_difference[i], over);
  }
  std::printf("\n");
}

// Solves by `solve` (a callable filling its SolveSummary) and prints one row of the table and the
// re-simulation's line.
template <typename Solve>
void Run(const char* solver, const ttz::lap::Vehicle& v, const ttz::lap::RoadTrack& road,
         size_t nodes, Solve solve) {
  using namespace ttz::lap;
  SolveSummary s;
  const double cpu_start = CpuSeconds();
  const LapSolution sol = solve(&s);
  const double cpu_us_per_node = 1e6 * (CpuSeconds() - cpu_start) / std::max(1, s.iterations) / nodes;
  const ResimReport r = Resimulate(v, road, sol, ResimOptions{});
  std::printf("%-9s %10.4f %12.4f %5d %6d %9.1f %10.3f %11.0f %8.0f %9.4f %8.3f %-9s %s\n", solver,
              sol.lap_time, sol.lap_time_extrapolated, s.converged ? 1 : 0, s.iterations,
              s.solve_seconds, s.solve_seconds / std::max(1, s.iterations), cpu_us_per_node,
              PeakMegabytes(), 100.0 * r.lap_time_relative,
              100.0 * r.max_state_difference_all, kStateNames[r.worst_state], s.message.c_str());
  PrintResimByState(r, ResimOptions{}.tolerance);
}

// TEXT as a number, all of it; else std::invalid_argument naming WHAT.
double Number(const std::string& text, const std::string& what) {
  if (const std::optional<double> x = ttz::ParseDouble(text)) return *x;
  throw std::invalid_argument(what + ": '" + text + "' is not a number");
}

// What the KEY=VALUE arguments set.
struct Settings {
  std::vector<std::string> bike;  // bike.yaml overrides, as `lap --set`
  ttz::lap::IndirectOptions indirect;
  ttz::lap::IpoptOptions ipopt;
  std::optional<bool> racing_line;  // the guess (`lap --guess`): unset, each solver's default
};

// The indirect solver's options that `indirect.NAME=VALUE` sets, by NAME.
struct IndirectKey {
  const char* name;
  void (*set)(ttz::lap::IndirectOptions*, double);
};
constexpr IndirectKey kIndirectKeys[] = {
    {"window_m", [](ttz::lap::IndirectOptions* o, double x) { o->window_m = x; }},
    {"window_overlap_m", [](ttz::lap::IndirectOptions* o, double x) { o->window_overlap_m = x; }},
    {"window_min_m", [](ttz::lap::IndirectOptions* o, double x) { o->window_min_m = x; }},
    {"window_eps_end", [](ttz::lap::IndirectOptions* o, double x) { o->window_eps_end = x; }},
    {"window_charge_price_s_per_j",
     [](ttz::lap::IndirectOptions* o, double x) { o->window_charge_price_s_per_j = x; }},
    {"eps_end", [](ttz::lap::IndirectOptions* o, double x) { o->eps_end = x; }},
    {"eps_floor", [](ttz::lap::IndirectOptions* o, double x) { o->eps_floor = x; }},
    {"num_threads", [](ttz::lap::IndirectOptions* o, double x) { o->num_threads = static_cast<int>(x); }},
    {"max_iterations", [](ttz::lap::IndirectOptions* o, double x) { o->max_iterations = static_cast<int>(x); }},
    {"path_tolerance", [](ttz::lap::IndirectOptions* o, double x) { o->path_tolerance = x; }},
    {"corrector_iterations",
     [](ttz::lap::IndirectOptions* o, double x) { o->corrector_iterations = static_cast<int>(x); }},
    {"corrector_contraction_max",
     [](ttz::lap::IndirectOptions* o, double x) { o->corrector_contraction_max = x; }},
    {"arclength_contraction_max",
     [](ttz::lap::IndirectOptions* o, double x) { o->arclength_contraction_max = x; }},
    {"arclength_max_turn_rad",
     [](ttz::lap::IndirectOptions* o, double x) { o->arclength_max_turn_rad = x; }},
    {"current_widening", [](ttz::lap::IndirectOptions* o, double x) { o->current_widening = x; }},
    {"current_model_eps", [](ttz::lap::IndirectOptions* o, double x) { o->current_model_eps = x; }},
    {"homotopy", [](ttz::lap::IndirectOptions* o, double x) { o->homotopy = x != 0.0; }},
    {"homotopy_handoff", [](ttz::lap::IndirectOptions* o, double x) { o->homotopy_handoff = x; }},
    {"homotopy_tolerance", [](ttz::lap::IndirectOptions* o, double x) { o->homotopy_tolerance = x; }},
    {"arclength_dlogeps", [](ttz::lap::IndirectOptions* o, double x) { o->arclength_dlogeps = x; }},
    {"window_homotopy_handoff",
     [](ttz::lap::IndirectOptions* o, double x) { o->window_homotopy_handoff = x; }},
    {"node_share_path", [](ttz::lap::IndirectOptions* o, double x) { o->node_share_path = x != 0.0; }},
    {"verbose", [](ttz::lap::IndirectOptions* o, double x) { o->verbose = x != 0.0; }},
};

// `indirect.NAME=VALUE` (NAME = key without its prefix): sets option NAME of kIndirectKeys, else
// std::invalid_argument listing them.
void SetIndirect(const std::string& key, const std::string& name, const std::string& value,
                 ttz::lap::IndirectOptions* indirect) {
  std::string names;
  for (const IndirectKey& k : kIndirectKeys) {
    if (name == k.name) return k.set(indirect, Number(value, key));
    names += (names.empty() ? "indirect." : ", indirect.") + std::string(k.name);
  }
  throw std::invalid_argument(key + ": not an option of lap_bench (" + names + ")");
}

// One KEY=VALUE argument: `indirect.NAME` the indirect solver's option NAME (SetIndirect),
// `ipopt.NAME` Ipopt's option NAME (IpoptOptions::extra, checked when Ipopt starts),
// `guess=centre-line` or `guess=racing-line` the initial guess (`lap --guess`), any other key
// overrides bike.yaml.
void ParseSetting(const std::string& a, Settings* settings) {
  const size_t eq = a.find('=');
  const std::string key = a.substr(0, eq), value = eq == std::string::npos ? "" : a.substr(eq + 1);
  if (key.rfind("indirect.", 0) == 0) SetIndirect(key, key.substr(9), value, &settings->indirect);
  else if (key.rfind("ipopt.", 0) == 0 && eq != std::string::npos) settings->ipopt.extra.emplace_back(key.substr(6), value);
  else if (key == "guess" && (value == "centre-line" || value == "racing-line")) settings->racing_line = value == "racing-line";
  else if (key == "guess") throw std::invalid_argument("guess: '" + value + "', expected centre-line or racing-line");
  else settings->bike.push_back(a);
}

int Bench(int argc, char** argv) {
  using namespace ttz::lap;
  ttz::SetLogLevel(2);  // progress (window, continuation steps) on stderr
  Settings settings;
  if (argc > 7) settings.indirect.eps_start = Number(argv[7], "EPS_START");
  settings.indirect.window_charge_price_s_per_j = NAN;  // NaN: the QSS lap's, as `lap`
  for (int i = 8; i < argc; ++i) ParseSetting(argv[i], &settings);
  const IpoptOptions& ipopt = settings.ipopt;
  const Vehicle v = MakeVehicle(LoadBike(argv[2], settings.bike));
  const RoadTrack road(ttz::ReadRoad(argv[1]));
  IndirectOptions indirect = settings.indirect;
  indirect.window_guess = QssWindowGuess(v, road);  // as `lap`
  MeshOptions mesh_options;
  mesh_options.ds_m = Number(argv[3], "DS_M");
  if (argc > 6) mesh_options.dt_max_s = Number(argv[6], "DT_MAX_S");
  const double length = std::min(Number(argv[4], "LENGTH_M"), road.Length());
  const std::vector<double> mesh = LapMesh(v, road, length, mesh_options);
  const std::string which = argc > 5 ? argv[5] : "both";
  const QssLap centre = ComputeQss(v, road, mesh);
  if (std::isnan(indirect.window_charge_price_s_per_j))
    indirect.window_charge_price_s_per_j = QssChargePrice(v, road, mesh, centre);
  const QssLap racing = ComputeQss(v, road, mesh, ComputeRacingLine(road, mesh, v.border_margin));
  // As `lap`: the racing line for the indirect solver, the centre line for Ipopt, unless `guess=`.
  const QssLap& for_indirect = settings.racing_line.value_or(true) ? racing : centre;
  const QssLap& for_ipopt = settings.racing_line.value_or(false) ? racing : centre;
  std::printf("%zu nodes over %.1f m, QSS lap %.4f s on the centre line, %.4f s on the racing line, "
              "windows' charge price %.3f s/MJ\n", mesh.size(), mesh.back(), centre.lap_time, racing.lap_time,
              1e6 * indirect.window_charge_price_s_per_j);
  std::printf("%-9s %10s %12s %5s %6s %9s %10s %11s %8s %9s %8s %-9s\n", "solver", "lap_s", "extrap_s",
              "conv", "iters", "wall_s", "s_per_iter", "cpu_us_node", "peak_MB", "resim_t%",
              "resim_x%", "worst");
  if (which != "ipopt")
    Run("indirect", v, road, mesh.size(), [&](SolveSummary* s) {
      return SolveIndirect(v, road, mesh, for_indirect.x, {}, for_indirect.u, indirect, s);
    });
  if (which != "indirect")
    Run("ipopt", v, road, mesh.size(), [&](SolveSummary* s) {
      return SolveDirectIpopt(v, road, mesh, for_ipopt.x, for_ipopt.u, ipopt, s);
    });
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ttz::KeepFreedMemory();
  if (argc < 5) {
    std::fprintf(stderr, "usage: lap_bench ROAD.h5 BIKE.yaml DS_M LENGTH_M [indirect|ipopt|both] [DT_MAX_S] [EPS_START] [KEY=VALUE ...]\n");
    return 2;
  }
  try {
    return Bench(argc, argv);
  } catch (const std::exception& e) {  // a bad argument or input file: the rows printed so far stay
    std::fflush(stdout);
    std::fprintf(stderr, "lap_bench: %s\n", e.what());
    return 2;
  }
}
