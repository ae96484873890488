// The oracle of the lap solver (issue 3): the direct transcription of the same model, solved as a
// nonlinear program by Ipopt (interior point, exact Hessians by second-order automatic differentiation (HyperDual),
// MUMPS). It shares nothing with the indirect solver (lap/solver/indirect.h) but the model, so
// their agreement tests both.
//
// Transcription on the mesh s_0 < ... < s_N, h_k = s_{k+1} - s_k: the indirect solver's implicit
// midpoint rule with one control per interval (lap/solver/indirect.cc, docs/lap.md "Solver
// design"), so that both solve the same discrete problem on the same mesh. Unknowns: the scaled
// states x~_k at the nodes and the scaled controls u~_k of the intervals (DefaultScales, order
// one); interval k is evaluated at its midpoint z_k = ((x~_k + x~_{k+1}) / 2, u~_k), with the road
// at s_{k+1/2} = (s_k + s_{k+1}) / 2:
//   minimise    sum_k h_k / sdot(z_k)                                (eq. 38, lap time)
//               + c sum_k sum_i (u~_{k,i} - u~_{k-1,i})^2 / ((h_{k-1} + h_k) / 2)  (below)
//   subject to  x~_{k+1} - x~_k - h_k x~'(z_k) = 0                   (eq. 36-37, implicit midpoint)
//               g_j(z_k) <= 0 for every constraint j and interval k (eq. 39a-g, constraints.h)
//               g_j(x~_k) <= 0 at every node k >= 1 (IpoptOptions::node_constraints)
//               x~_0 = x_guess[0] / S                                 (start state fixed)
// The end state is free (paper). The inequalities are Ipopt constraints, not barrier penalties of
// the Hamiltonian: the answer has eps = 0. With node constraints, the constraints that bound one
// state (the borders, roll and yaw rates, charge and brake torque: IsStateBound) are bounds of
// the nodes' unknowns, and their rows at the midpoints are left out where the nodes' bounds imply
// them (everywhere on a road of constant width): the same feasible set with 12 inequality rows
// per interval instead of 26 (docs/lap.md, "Bounds and HyperDual Hessians", has what it saves).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct IpoptOptions {
  // Ipopt's `tol`: the largest scaled NLP error (dual infeasibility, constraint violation,
  // complementarity) at convergence.
  double tolerance = 1e-8;
  // Ipopt's `max_iter`.
  int max_iterations = 3000;
  // Ipopt's `print_level`: 0 silent, 5 one line per iteration and a final statistics block.
  int print_level = 0;
  // c [s m] of an optional control-rate term c * integral |du~/ds|^2 ds (between interval
  // midpoints) added to the objective; the reported lap time excludes it. Off by default: since
  // Omega_z and tau_w became states (lap/model/state.h) with their rates' cost in the model
  // (lap/model/cost.h), the answer is smooth without it, and the oracle solves the same problem as
  // the indirect solver. Measured on the 300 m bend road of oracle_test (2 m mesh): c = 0,
  // 14.3306 s in 34 iterations; c = 1e-4, 14.3315 s in 39.
  double control_rate_weight = 0.0;
  // Ipopt's `mu_strategy`: "adaptive" or "monotone". Both converge on the roads above;
  // adaptive took 8 and 60 iterations (straight, bend), monotone 131 and 203.
  std::string mu_strategy = "adaptive";
  // Ipopt's `mu_init`, the first barrier weight (Ipopt's default 0.1). With "monotone" and 1e-4,
  // gear 4.0 with a 30 MJ pack, warm-started from gear 3.7's lap, took 61 iterations where the
  // adaptive barrier crawled (cold with either globalization, warm with the default; docs/lap.md,
  // "A monotone barrier from a neighbouring lap").
  double mu_init = 0.1;
  // Ipopt's `adaptive_mu_globalization`: how the adaptive strategy judges that a barrier value
  // has made progress, "obj-constr-filter" (Ipopt's default) or "kkt-error". Neither is better on
  // every lap (docs/lap.md, "Ipopt's barrier globalization"; whole course, 40 m with at most 1 s):
  // with a pack a little short of what the lap at full current uses, the filter kept the barrier
  // near 1e-3 for thousands of iterations (gear 3.4, 37 MJ: failed after 3000; gear 2.8, 30 MJ:
  // 1211) where "kkt-error" took 345 and 324; with a pack far short the filter took 149-164 and
  // "kkt-error" had not converged after 190.
  std::string mu_globalization = "obj-constr-filter";
  // Check every constraint at the nodes 1..N as well as at the midpoints. With the midpoints alone
  // a state constrained there (the roll rate, say) may overshoot its limit at a node between two
  // midpoints where it is active, and lap.h5, which reports the nodes, shows the overshoot: on the
  // TT course at 180 A per motor, roll rate 34 % and adherence 20 % over (docs/lap.md,
  // "Constraints at the nodes"). Off only to measure what the nodes change (ipopt_direct_test).
  bool node_constraints = true;
  // Threads for the midpoint evaluations (80 % of the time with one thread; Ipopt's own linear
  // algebra, MUMPS, is sequential).
  int num_threads = 2;
  // Further Ipopt options by name and value, e.g. {"mumps_pivtol", "1e-8"}, set after (and so
  // over) the ones above, as Ipopt's type for the name reads the value: for experiments with
  // Ipopt's own settings (`lap_bench ... ipopt.NAME=VALUE`). An unknown name or a value Ipopt
  // rejects throws std::invalid_argument.
  std::vector<std::pair<std::string, std::string>> extra;
};

// Solves from the guess (x_guess[0] is the fixed start state; the controls start at the mean of
// u_guess at the interval's two nodes). The answer is checked after Ipopt reports success: the
// largest scaled midpoint state defect must be <= 1e-6 and every constraint g_j <= 1e-4
// (relative) at every midpoint (and node, with node constraints), else summary->converged is false and summary->message says why.
// Returned: x at the nodes; u at a node = the mean of its neighbouring intervals' controls (an end
// node: its one interval's), as the indirect solver reports them; lambda = the costates of the
// scaled states at the nodes from the defect multipliers (ipopt_direct.cc,
// CostatesFromMultipliers); eps = 0; lap_time = lap_time_extrapolated = the lap time of the
// objective; summary->max_residual = Ipopt's final scaled NLP error, summary->steps empty,
// summary->control_failures 0. Ipopt takes the guess's states and controls (those of the
// intervals when it has them) and initialises its multipliers itself: warm-starting them from an
// earlier lap's did not save iterations (docs/lap.md, "Warm starts on the
// earlier lap's mesh"). Throws std::invalid_argument when Ipopt rejects a value of `options`.
LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh, const SolverGuess& guess,
                             const IpoptOptions& options, SolveSummary* summary);
// The same from states and controls alone.
LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh,
                             const std::vector<StateVector<double>>& x_guess,
                             const std::vector<ControlVector<double>>& u_guess,
                             const IpoptOptions& options, SolveSummary* summary);

}  // namespace ttz::lap
