// What a lap solver returns, whichever solver it is (lap/solver/indirect.h, the Ipopt oracle):
// the optimal states, costates and controls on the mesh, and a summary whose `converged` comes
// from the solver's own checks of its answer, never from the optimiser's word alone.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "lap/model/constraints.h"
#include "lap/model/state.h"

namespace ttz::lap {

struct ContinuationStep {
  double eps = 0.0;       // barrier weight [1]
  double lap_time = 0.0;  // [s]
  int iterations = 0;
  double seconds = 0.0;
  bool converged = false;
};

struct LapSolution {
  std::vector<double> s;                       // mesh [m]
  std::vector<StateVector<double>> x;          // states (physical units)
  std::vector<StateVector<double>> lambda;     // costates of the scaled states [s]
  std::vector<ControlVector<double>> u;        // controls at the nodes, mean of the intervals' (physical units)
  std::vector<ControlVector<double>> u_interval;  // the transcription's control of each mesh interval
  std::vector<double> t;                       // time [s]
  double eps = 0.0;                            // barrier weight of this solution (0: none)
  double lap_time = 0.0;                       // at eps [s]
  double lap_time_extrapolated = 0.0;          // linear extrapolation to eps = 0 [s]
};

// Where a solve starts, on its mesh: the states, the costates of the scaled states
// (lap/solver/hamiltonian.h; empty: from the states alone), and the controls at the nodes and of
// the intervals (the Ipopt oracle starts from u_interval, or when it is empty from the mean of
// the nodes'; the indirect solver from the nodes').
struct SolverGuess {
  std::vector<StateVector<double>> x, lambda;
  std::vector<ControlVector<double>> u, u_interval;
};

// A guess of a window of the indirect solver's first step (IndirectOptions::window_guess) on
// `mesh` from the state `start` at its first node: states and controls at its nodes.
using WindowGuess =
    std::function<void(const StateVector<double>& start, const std::vector<double>& mesh,
                       std::vector<StateVector<double>>* x, std::vector<ControlVector<double>>* u)>;

// The controls at the nodes from the intervals' (both solvers hold one control per interval): a
// node reports the mean of its two neighbouring intervals' controls, an end node its one
// interval's.
inline std::vector<ControlVector<double>> NodeControls(
    const std::vector<ControlVector<double>>& u_interval) {
  const size_t intervals = u_interval.size();
  std::vector<ControlVector<double>> u(intervals + 1);
  for (size_t node = 0; node <= intervals; ++node)
    for (int i = 0; i < kNumControls; ++i) {
      if (node == 0) u[node][i] = u_interval[0][i];
      else if (node == intervals) u[node][i] = u_interval[node - 1][i];
      else u[node][i] = 0.5 * u_interval[node - 1][i] + 0.5 * u_interval[node][i];
    }
  return u;
}

struct SolveSummary {
  bool converged = false;                      // every check below passed
  std::string message;                         // why not, when not
  std::vector<ContinuationStep> steps;         // barrier continuation (indirect solver)
  int iterations = 0;                          // optimiser iterations in all steps
  double solve_seconds = 0.0;
  double max_residual = 0.0;                   // scaled, of the final system
  double max_state_defect = 0.0;               // largest scaled state defect of the transcription
  // Per constraint kind (kConstraintNames), the largest g_j over the points the solver checks: the
  // interval midpoints, where the transcription evaluates the model, and with the Ipopt oracle's
  // node constraints (ipopt_direct.h) the nodes too.
  std::vector<double> max_violation;
  int control_failures = 0;                    // nodes whose H_u = 0 Newton did not converge
  bool first_step_in_windows = false;          // the indirect solver's first step was solved in
                                               // windows (IndirectOptions::window_m)
};

// Why the solve did not converge: the summary's message without its trailing separator ("" when
// it converged).
inline std::string SolveMessage(const SolveSummary& summary) {
  std::string why = summary.message;
  while (!why.empty() && (why.back() == ' ' || why.back() == ';')) why.pop_back();
  return why;
}

}  // namespace ttz::lap
