// The oracle of the lap solver (issue 3): the direct transcription of the same model, solved as a
// nonlinear program by Ipopt (interior point, exact Hessians by nested automatic differentiation,
// MUMPS). It shares nothing with the indirect solver (lap/solver/indirect.h) but the model, so
// their agreement tests both.
//
// Transcription on the mesh s_0 < ... < s_N, h_k = s_{k+1} - s_k, unknowns z_k = (x~_k, u~_k) at
// every node (states and controls scaled by DefaultScales, order one):
//   minimise    sum_k h_k / 2 (1/sdot_k + 1/sdot_{k+1})              (eq. 38, lap time)
//               + c sum_k sum_i (u~_{k+1,i} - u~_{k,i})^2 / h_k       (control rate, below)
//   subject to  x~_{k+1} - x~_k - h_k / 2 (x~'_k + x~'_{k+1}) = 0      (eq. 36-37, trapezoidal)
//               g_j(x_k, u_k) <= 0 for every constraint j and node k  (eq. 39a-g, constraints.h)
//               x~_0 = x_guess[0] / S                                  (start state fixed)
// The end state is free (paper). The inequalities are Ipopt constraints, not barrier penalties of
// the Hamiltonian: the answer has eps = 0.
#pragma once

#include <string>
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
  // c [s m] of the control-rate term c * integral |du~/ds|^2 ds added to the objective. With the
  // controls at the nodes and the trapezoidal rule, an alternating ("odd-even") mode of the
  // controls changes neither the defects nor the lap time to first order, so it is nearly free
  // and rings (lap-solver notes); this term damps it. The reported lap time excludes the term.
  // Measured on a 300 m road, 8 m wide, with a 50 m radius bend from 100 to 220 m (curvature
  // ramped over 20 m at each end), 2 m mesh, bx15, from the QSS guess: c = 0 rings in the braking
  // torque by up to +-300 N m node to node and takes 14.212 s, 0.56 % less than c = 1e-4 started
  // from that answer (14.293 s, smooth); c = 3e-5, 1e-4, 3e-4, 1e-3 give 14.292, 14.295, 14.315,
  // 14.327 s (the first two are different local optima). On the straight of ipopt_direct_test
  // the lap moves by < 1e-7 relative between c = 1e-4 and 1e-3.
  double control_rate_weight = 1e-4;
  // Ipopt's `mu_strategy`: "adaptive" or "monotone". Both converge on the roads above;
  // adaptive took 16 and 57 iterations (straight, bend), monotone 233 and 87.
  std::string mu_strategy = "adaptive";
  // Threads for the node evaluations (80 % of the time with one thread; Ipopt's own linear
  // algebra, MUMPS, is sequential).
  int num_threads = 2;
};

// Solves from the guess (x_guess[0] is the fixed start state). The answer is checked after Ipopt
// reports success: the largest scaled trapezoidal state defect must be <= 1e-6 and every
// constraint g_j <= 1e-4 (relative), else summary->converged is false and summary->message says
// why. Returned: lambda = the costates of the scaled states from the defect multipliers
// (ipopt_direct.cc, CostatesFromMultipliers), eps = 0, lap_time = lap_time_extrapolated = the
// lap time of the objective; summary->max_residual = Ipopt's final scaled NLP error,
// summary->steps empty, summary->control_failures 0.
LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh,
                             const std::vector<StateVector<double>>& x_guess,
                             const std::vector<ControlVector<double>>& u_guess,
                             const IpoptOptions& options, SolveSummary* summary);

}  // namespace ttz::lap
