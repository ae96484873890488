// The re-simulation check of a lap solution (issue 3: "integrate the state equations forward with
// the optimal controls at a finer step and report the lap-time and state differences; they must
// agree within 0.1 %").
//
// What is integrated: x' = dx/ds = f(x, u(s), road(s)) (eq. 36-37, lap/model/dynamics.h) and
// t' = 1 / sdot (eq. 38, sdot from eq. 10a), with
// - the controls held constant on each mesh interval at the solution's `u_interval`, as both
//   solvers' implicit midpoint rule has them (lap/solver/transcription.h); for a solution without
//   them (a hand-made lap), piecewise linear in s through the node values `u`.
// - the road evaluated at every stage by RoadTrack::At;
// - the adaptive Dormand-Prince 5(4) pair, each mesh interval in at least `min_substeps` steps
//   ending on its nodes (the controls' kinks). Adaptive because the model is stiff: the wheel's
//   slip mode decays at ~5500 / V [1/s] (measured: 1094 /s at the 5 m/s start, 117 /s at 46 m/s),
//   so a fixed RK4 at a quarter of a 2 m mesh (h lambda ~ -110 at the start; RK4 is stable to
//   -2.8) diverges, and the tyre's vertical mode (-1.7 +- 26.2i /s, 4.2 Hz) needs a few steps
//   per period.
//
// Why windows: the bike's roll is an inverted pendulum. With the yaw rate prescribed (a state
// driven by the control dOmega_z/dt, lap/model/state.h) the forward integration has one unstable mode, measured at +3.8 to +4.2 /s
// (time constant 0.24 to 0.27 s) on a straight and on a 50 m radius bend, whatever the speed.
// Any difference between the transcription (second order in h) and the true dynamics, and even
// rounding, grows by e every quarter second: integrated open loop, the bike falls over (measured,
// Ipopt's lap of a 300 m straight, 2 m mesh: roll rate off by 10 % at 100 m, capsized at 120 m,
// from a rounding-level asymmetry; with a 50 m bend, off by > 100 % within 6 m of the start).
// The check therefore restarts from the solution's state at the first node of every window of
// `window_seconds` of the solution's time (whole mesh intervals, at least one) and integrates to
// the window's last node; within a window the unstable mode amplifies a local error by at most
// e^(window / 0.25 s). The criterion then reads: at every node, each state integrated from the
// solution's state at most one window back differs from the solution by at most `tolerance` of
// the state's scale (below), and the lap time - the sum of the windows' times, each integrated
// from its start - differs from the solution's by at most `tolerance` of it.
//
// State scales: each state's difference is divided by max(range of the state along the
// solution, floor), the floor being DefaultScales (lap/solver/hamiltonian.h) except for the
// energy e, whose floor is 1 % of the pack (DefaultScales' full pack would make 0.1 % mean
// 51 kJ whatever the lap uses). The range makes 0.1 % mean 0.1 % of what the state does on the
// lap; the floor keeps states that hardly vary (n, phi on a straight) from dividing by zero.
#pragma once

#include <string>
#include <vector>

#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct ResimOptions {
  // The integration restarts from the solution's state every `window_seconds` of the solution's
  // time (whole mesh intervals, at least one); at least the lap time: one open-loop window.
  // 0.25 s is the roll mode's time constant (above): a local error grows at most e-fold.
  double window_seconds = 0.25;
  // Fewest integration steps per mesh interval (the step is at most h_k / min_substeps).
  int min_substeps = 4;
  // Local error per step of the Dormand-Prince pair, relative to max(DefaultScales, |x|) per
  // state (and to max(1 s, t) for the time).
  double step_tolerance = 1e-9;
  // The pass criterion: lap time and every state within this fraction (0.1 %, issue 3).
  double tolerance = 1e-3;
  // A window is abandoned (and the check failed) once a state's scaled difference exceeds this,
  // or the model is undefined (sdot <= 0, non-finite): it has diverged and measures no more.
  double abandon_difference = 1.0;
};

struct ResimReport {
  bool passed = false;                // both differences within options.tolerance
  std::string message;                // why not, when not ("" otherwise)
  double lap_time = 0.0;              // sum of the windows' times [s] (NaN when a window diverged)
  double lap_time_difference = 0.0;   // lap_time - the solution's [s]
  double lap_time_relative = 0.0;     // |lap_time_difference| / the solution's lap time [1]
  StateVector<double> scale{};        // per state: max(range along the solution, floor)
  StateVector<double> max_state_difference{};  // per state: max over nodes of |x_resim - x| / scale
  double max_state_difference_all = 0.0;       // the largest of those [1]
  // per node and state: |x_resim - x| / scale [1], x_resim integrated from the first node of the
  // node's window (0 at s = 0), NaN at the nodes not reached (past a window that diverged)
  std::vector<StateVector<double>> state_difference;
  int worst_state = 0;                // the state and node s [m] of the largest
  double worst_s = 0.0;
  int windows = 0;                    // windows integrated
};

// Each state's scale: max(range along sol.x, floor) (above).
StateVector<double> ResimStateScales(const Vehicle& v, const LapSolution& sol);

// Re-simulates `sol` (its s, x, u, t) on `road` with the vehicle `v`.
ResimReport Resimulate(const Vehicle& v, const RoadTrack& road, const LapSolution& sol,
                       const ResimOptions& options);

}  // namespace ttz::lap
