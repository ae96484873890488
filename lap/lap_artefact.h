// lap.h5: the optimal lap on its arc-length mesh (schema "ttz.lap", version 4), and the part of it
// that warm-starts another solve (`lap --init`). Every dataset, unit and attribute is documented
// in docs/lap_h5.md.
#pragma once

#include <string>
#include <vector>

#include "lap/lap_channels.h"
#include "lap/mesh.h"
#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/qss.h"
#include "lap/resimulate.h"
#include "lap/sensitivity.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

inline constexpr const char* kLapSchema = "ttz.lap";
inline constexpr int kLapSchemaVersion = 4;  // 2: Omega_z a state, dOmega_z_dt a control; 3: control_interval;
                                             // 4: sensitivity/*
inline constexpr int kLapOldestWarmStartVersion = 2;  // --init reads version 2 too (no control_interval)

// The options the solver ran with, as lap.h5 records them.
struct LapSolverOptions {
  int max_iterations = 0;        // the iteration limit in effect (--max-iterations or the solver's default)
  std::string mu_globalization;  // Ipopt's adaptive_mu_globalization; "" for the indirect solver
  std::string mu_strategy;       // Ipopt's mu_strategy; "" for the indirect solver
  double mu_init = 0.0;          // Ipopt's mu_init [1]; 0 for the indirect solver
  double window_m = 0.0;          // the indirect solver's windows (IndirectOptions) [m]; 0 for Ipopt
  double window_overlap_m = 0.0;  // their overlap [m]; 0 for Ipopt
  double window_eps_end = 0.0;    // the weight the windows go down to [1]; 0 without windows
  double window_charge_price_s_per_j = 0.0;  // at the windows' ends (IndirectOptions) [s/J]
};

// What lap.h5 records about the run besides the solution.
struct LapProvenance {
  std::string solver;        // "indirect" or "ipopt"
  std::string bike_yaml;     // the bike as used (after --set), BikeToYaml
  std::string road_file;     // as given on the command line
  std::string road_sha256;   // FileSha256 of road_file
  double road_length = 0.0;  // [m]
  std::string init_file;     // the --init file, "" when none
  MeshOptions mesh;          // how the mesh was built (--ds, --dt-max)
  bool mesh_from_init = false;  // the mesh is the --init file's (lap/main.cc, UseInitMesh)
  std::string guess;            // where the solve started: "racing-line", "centre-line" (--guess) or "init"
  double guess_lap_time = 0.0;  // the guess's lap time [s] (the QSS lap's on its line; 0 with --init)
  std::string start = "standing";  // "standing" (bike.yaml's initial speed) or "flying" (--start)
  LapSolverOptions solver_options;
};

// Writes atomically (ttz::ArtefactWriter); also when the solve did not converge. The costates
// are written as those of the physical states (the solver's scaled ones divided by the scales).
// `sensitivities` (lap/sensitivity.h) go to sensitivity/*, written only when there are any.
void WriteLap(const std::string& path, const Vehicle& v, const LapSolution& sol,
              const SolveSummary& summary, const LapChannels& channels, const QssLap& qss,
              const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities,
              const LapProvenance& provenance);

// An earlier solution, as read from its lap.h5.
struct WarmStart {
  std::vector<double> s;                     // [m]
  std::vector<StateVector<double>> x;        // states (physical units)
  std::vector<StateVector<double>> lambda;   // costates of the physical states [s per state unit]
  std::vector<ControlVector<double>> u;      // controls (physical units)
  std::vector<ControlVector<double>> u_interval;  // ... of the mesh intervals (physical units)
  double eps = 0.0;                          // barrier weight of the solution [1]
  MeshOptions mesh;                          // the options its mesh was built with
  std::string start = "standing";            // its `start` ("standing" in files without one)
  std::string road_sha256;
  double road_length = 0.0;                  // [m]
};

// Throws ttz::InputError naming the file and the dataset or attribute when the file is missing,
// is not a ttz.lap artefact of version kLapOldestWarmStartVersion to kLapSchemaVersion (version 2:
// u_interval empty), lacks a dataset or attribute, or its datasets disagree.
WarmStart ReadLapForWarmStart(const std::string& path);

// The warm start on another mesh, linearly interpolated in s (clamped to the file's range; the
// intervals' controls at the intervals' midpoints), with the costates scaled as the solver takes
// them (lap/solver/hamiltonian.h, DefaultScales of v).
SolverGuess ResampleWarmStart(const WarmStart& w, const Vehicle& v, const std::vector<double>& mesh);

}  // namespace ttz::lap
