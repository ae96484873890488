// Benchmark of the lap solvers on a piece of a road.h5 (e.g. the Snaefell course that `make run`
// fits): both solvers from the QSS guess on the mesh of `lap --ds DS_M --dt-max DT_MAX_S` (lap/mesh.h)
// from 0 to LENGTH_M, printing lap time, convergence, iterations, wall time, time per iteration,
// CPU time (all threads) per iteration and node, peak memory and the re-simulation check's
// lap-time and largest state difference (not a test). KEY=VALUE arguments after EPS_START override
// bike.yaml values as `lap --set` does; `indirect.window_m=M` and `indirect.window_overlap_m=M`
// set the indirect solver's options of those names, `ipopt.NAME=VALUE` Ipopt's option NAME (e.g.
// `ipopt.print_level=5`). CPU time per iteration and node is the figure to compare across
// meshes: other processes sharing the machine do not count in it.
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "common/log.h"
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

// Solves by `solve` (a callable filling its SolveSummary) and prints one row of the table.
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
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ttz::lap;
  if (argc < 5) {
    std::fprintf(stderr, "usage: lap_bench ROAD.h5 BIKE.yaml DS_M LENGTH_M [indirect|ipopt|both] [DT_MAX_S] [EPS_START] [KEY=VALUE ...]\n");
    return 2;
  }
  ttz::SetLogLevel(2);  // progress (window, continuation steps) on stderr
  // KEY=VALUE arguments: `indirect.window_m=M` and `indirect.window_overlap_m=M` set the
  // indirect solver's IndirectOptions of those names, `ipopt.NAME=VALUE` Ipopt's option NAME
  // (IpoptOptions::extra), the others override bike.yaml.
  std::vector<std::string> bike_overrides;
  std::map<std::string, double> solver_settings;
  IpoptOptions ipopt;
  for (int i = 8; i < argc; ++i) {
    const std::string a = argv[i];
    const size_t dot = a.find('.'), eq = a.find('=');
    const std::string prefix = eq == std::string::npos || dot > eq ? "" : a.substr(0, dot);
    if (prefix == "indirect") solver_settings[a.substr(dot + 1, eq - dot - 1)] = std::stod(a.substr(eq + 1));
    else if (prefix == "ipopt") ipopt.extra.emplace_back(a.substr(dot + 1, eq - dot - 1), a.substr(eq + 1));
    else bike_overrides.push_back(a);
  }
  const auto solver_setting = [&](const std::string& key, double fallback) {
    const auto it = solver_settings.find(key);
    return it == solver_settings.end() ? fallback : it->second;
  };
  const Vehicle v = MakeVehicle(LoadBike(argv[2], bike_overrides));
  const RoadTrack road(ttz::ReadRoad(argv[1]));
  MeshOptions mesh_options;
  mesh_options.ds_m = std::stod(argv[3]);
  if (argc > 6) mesh_options.dt_max_s = std::stod(argv[6]);
  const double length = std::min(std::stod(argv[4]), road.Length());
  const std::vector<double> mesh = LapMesh(v, road, length, mesh_options);
  const std::string which = argc > 5 ? argv[5] : "both";
  const QssLap qss = ComputeQss(v, road, mesh);
  std::printf("%zu nodes over %.1f m, QSS lap %.4f s\n", mesh.size(), mesh.back(), qss.lap_time);
  std::printf("%-9s %10s %12s %5s %6s %9s %10s %11s %8s %9s %8s %-9s\n", "solver", "lap_s", "extrap_s",
              "conv", "iters", "wall_s", "s_per_iter", "cpu_us_node", "peak_MB", "resim_t%",
              "resim_x%", "worst");
  if (which != "ipopt")
    Run("indirect", v, road, mesh.size(), [&](SolveSummary* s) {
      IndirectOptions o;
      if (argc > 7) o.eps_start = std::stod(argv[7]);
      o.window_m = solver_setting("window_m", o.window_m);
      o.window_overlap_m = solver_setting("window_overlap_m", o.window_overlap_m);
      return SolveIndirect(v, road, mesh, qss.x, {}, qss.u, o, s);
    });
  if (which != "indirect")
    Run("ipopt", v, road, mesh.size(), [&](SolveSummary* s) {
      return SolveDirectIpopt(v, road, mesh, qss.x, qss.u, ipopt, s);
    });
  return 0;
}
