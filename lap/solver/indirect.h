// The indirect solver of the minimum-lap-time problem (eq. 38) by Ceres: the necessary conditions
// of the barrier-penalised problem, transcribed with the implicit midpoint rule on an arc-length mesh (transcription.h), as
// a square residual system in the states and costates of every node (controls eliminated per node,
// lap/solver/node.h), solved by Levenberg-Marquardt (Newton with a large trust region) with sparse
// Cholesky, along a continuation of the barrier weight eps; the lap time is extrapolated to eps = 0.
// Design and evidence: ../shared/notes/lap-solver-prototype.md, docs/lap.md, docs/lap_log.md.
#pragma once

#include <vector>

#include "lap/model/constraints.h"
#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/road_track.h"
#include "lap/solver/hamiltonian.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct Transcription;

struct IndirectOptions {
  double eps_start = 1.0;        // first barrier weight [1]: on 300-400 m roads with bends 0.1
                                 // stalls the first solve and 1 converges (docs/lap.md)
  // When the first step at eps_start fails, the solve starts again from the guess at this weight
  // (0: never). On the 5 km roads (5 m mesh) it is the other way round: the first step at eps 1
  // ends in a local minimum of the least-squares cost, and from 0.1 the whole continuation
  // converges (docs/lap.md).
  double retry_eps_start = 0.1;
  double eps_end = 1e-4;         // last barrier weight [1]
  // Where the answer at eps_end violates a constraint by more than constraint_tolerance, the
  // continuation goes on down, halving the weight until the answer meets it, to at most this
  // weight [1]: a relaxed barrier's overshoot (its quadratic beyond -delta, delta = 0.1 eps:
  // hamiltonian.h) shrinks with eps, though not at once (the multiplier moves too). On the TT
  // course the charge at the finish of a 25 MJ pack overshot by 1.24e-4 of the pack at eps 1e-4
  // and by 6.6e-5 at 5e-5; a decade down at once, the residuals' floor at 1e-5 (~4e-8) missed
  // the final 1e-8 (docs/lap_log.md "Below eps_end"). eps_floor = eps_end: never.
  double eps_floor = 1e-6;
  double eps_factor = 0.7;       // eps_{k+1} = factor eps_k; halved in log on a failed step
  int max_retries = 4;           // failed continuation steps retried with a smaller factor
  int max_iterations = 300;      // Ceres iterations of the first continuation step
  int max_step_iterations = 60;  // of each later step (Newton from the last step: 5-15 when it
                                 // converges, and slow linear progress when it will not)
  double residual_tolerance = 1e-9;  // Ceres stops at ||residual|| <= this; a step must reach max 10x this
  // The same for the steps between the first and the last: on a 5 km piece of the TT course
  // (10 m mesh) the residuals' floor is ~1e-8 and with residual_tolerance every step there ran
  // into its iteration limit (docs/lap_log.md).
  double path_tolerance = 1e-7;
  double constraint_tolerance = 1e-4;  // largest allowed g_j > 0 (relative) in the answer
  // Barriers (and the check) of every constraint at the nodes 1..N as well as at the midpoints
  // (lap/solver/node_barrier.h): with the midpoints alone a state at its limit at two midpoints
  // may overshoot it at the node between them. Off only to compare with an earlier answer.
  bool node_constraints = true;
  // After the first step, follow the solution curve in (unknowns, log eps) by pseudo-arclength
  // steps (tangent predictor, Newton corrector on the bordered system by block elimination
  // with the sparse LU of J, or the LU of the bordered matrix where J is singular) instead of
  // shrinking eps with Levenberg-Marquardt. On the first 5 km of the TT course (10 m mesh,
  // eps_start 0.1) the curve is nearly vertical at eps ~3.4e-3 (d log eps / ds ~ 2e-3, the roll
  // weave at s ~2.9 km grows): Levenberg-Marquardt on the normal equations (condition squared,
  // sigma_min(J) ~ 1e-6) stalled there; the bordered Newton passes it (docs/lap_log.md).
  bool arclength = true;
  double arclength_dlogeps = 0.36;  // first step's change of log eps (~ log of eps_factor)
  // Newton iterations of an arclength step's corrector before the step is halved. On the first
  // 10 km of the TT course (20 m, at most 0.5 s) 12 instead of 8 took the steps from 39 (10
  // retried) to 29 (7), 27.9 to 24.5 s; on the whole course it took 69 steps (10 retried), 337
  // iterations, 384 s against 70, 327, 369 s with 8 (docs/lap_log.md, session 33).
  int corrector_iterations = 8;
  // A corrector of Newton's homotopy and of the node barriers' share path fails at once when a
  // Newton step is longer than this times the one before (CorrectorNotContracting,
  // solution_curve.h); infinity: never.
  double corrector_contraction_max = 0.5;
  // The same bound on the barrier continuation's correctors (TraceCurve); infinity: never. A
  // stopped corrector shortens the step, and the shorter steps may follow the curve into a
  // turning point that full correctors step over: on the TT course's first 5 km (5 m) 0.5 and 1
  // met one at eps 1.33e-4 and 1.36e-4, and 0.7 left the calibrated bike's weave at one at eps
  // 7.2e-4 instead of 3.0e-4. So where the path with the bound does not reach eps_end, it is
  // followed again without it (TraceCurve, indirect.cc). On the whole course (the benchmark of
  // docs/lap_log.md, session 51) 0.7 took 155.7 s and 3,727 iterations, 1 161.8 s and 3,655, none
  // 184.9 s and 3,914, one after the other, the same lap.
  double arclength_contraction_max = 0.7;
  // A step of the barrier continuation whose tangent turns by more than this [rad] is retried at
  // half its length (PathSettings::max_turn); infinity: never. On the TT course's first 5 km
  // (5 m) with the widened switch below, a step of 7.3 that turned by 1.37 rad came out with eps
  // rising, a turning point at eps 1.35e-4 that the shorter steps after a retry went through to
  // eps_end; the steps that converge turn by 0.2-0.65 rad (docs/lap_log.md "Session 54: a wider
  // switch while the barrier is heavy").
  double arclength_max_turn_rad = 1.0;
  // The motor current's driving/braking switch (i_m = f+(.) of width d, eq. 25: lap/model/
  // smooth.h) is smoothed wider while the barrier is heavy: at the weight eps its width is
  // d clamp(eps / current_model_eps, 1, current_widening) (Transcription::ModelAtWeight), the
  // model's own at and below current_model_eps, so that an answer at eps_end <= current_model_eps
  // and the lap time extrapolated from there are the model's (1: off). On the TT course gear 4.2
  // (192 A), which stopped at eps 9.9e-4 with the model's 2 A, converges with 6 A above eps 9e-4,
  // to Ipopt's extrapolated lap (docs/lap_log.md "Session 54: a wider switch while the barrier is
  // heavy"). Where the path with the widened switch stops at a weight above current_model_eps, it
  // is followed again from its start with the model's switch (FollowCurve, indirect.cc): gear
  // 4.1, which converged with the model's switch, stopped at eps 1.43e-3 with the wider one.
  double current_widening = 3.0;
  double current_model_eps = 3e-4;
  // The first step of a start near the solution at eps_start (node barriers on: the node
  // barriers added to the midpoints' solution, the whole road from its stitched windows, an
  // --init lap) by Newton's homotopy H(v, t) = F(v) - (1 - t) F(v0) = 0, followed from the start
  // v0 (t = 0) to F = 0 (t = 1) by the pseudo-arclength steps above (lap/solver/solution_curve.h),
  // instead of Levenberg-Marquardt; at a turning point in t, a failed step or after
  // max_iterations Newton iterations Levenberg-Marquardt takes over from v0. On the TT course
  // (20 m) the whole road's first step from its stitched windows took 40 Newton iterations, 43 s,
  // against Levenberg-Marquardt's 248, 254 s (docs/lap_log.md, session 34). From the QSS guess
  // itself it turned or crept (10 km of the course: 17,702 iterations in all against 1,610);
  // from a guess it starts where LM got near (homotopy_handoff).
  bool homotopy = true;
  // max |H| at the points before the end of Newton's homotopy and of the node barriers' share
  // path: only the end needs to solve F, the points only keep Newton's iterates near the path. On
  // the TT course (20 m, at most 0.5 s, 3 km windows) 1e-3 instead of 1e-5 took the first 10 km
  // from 682 iterations to 569 (1e-4: 656; 1e-2: 1,103, its steps failing) and the whole course
  // from 4,957 to 4,328, 208.0 s against 234.2 s, the same lap (docs/lap_log.md "Looser points on
  // the homotopies").
  double homotopy_tolerance = 1e-3;
  // From a guess Levenberg-Marquardt's first solve hands over to Newton's homotopy (above, with
  // homotopy on) where it first reaches ||F||_2 <= homotopy_handoff (0: never); where the
  // homotopy fails LM goes on from there. LM brings the QSS guess near the solution in 10-75
  // iterations and then often spends 100 and more wandering (its non-monotonic steps) and in a
  // slow tail (trust-region ratio ~0.75, the radius growing ~1.2x an iteration), a count that is
  // chaotic in its start. Off on whole roads: on the 5 km roads at 5 m the homotopy from there
  // crept (steps of ~0.01 in t) or turned, the first 5 km of the TT course took 964 iterations
  // against 668 and its calibrated bike did not converge (docs/lap_log.md "Levenberg-Marquardt
  // handing over to Newton's homotopy"). The windows use window_homotopy_handoff.
  double homotopy_handoff = 0.0;
  // From a guess without costates the first solve is of the midpoints' barriers alone
  // (SolveFrom, indirect.cc); the node barriers are then switched on at the same weight by
  // pseudo-arclength steps in their share of eps, from 0 to 1 (NodeBarrierPath,
  // solution_curve.h; the tolerance of its points homotopy_tolerance), before the first step
  // with them (which then starts at its solution). Where it fails, that first step starts from
  // the midpoints' solution as without it. On the TT course's first 3 km (20 m, at most 0.5 s)
  // it took 58 Newton iterations, 3.9 s, where Newton's homotopy turned after 6 and
  // Levenberg-Marquardt took 172 iterations, 9.1 s (docs/lap_log.md "The node barriers switched on
  // by their share").
  bool node_share_path = true;
  // The first step from a guess without costates, on a road longer than `window_m` [m] (0: never
  // windowed): solved window by window at eps_start (at retry_eps_start instead when that is set
  // and smaller: the weight at which the windows converged on the TT course, docs/lap_log.md), each
  // window's start state fixed by the previous window's solution and its end free (a window that
  // fails is solved again from `window_guess`, then at ten times the weight and followed down to
  // it), keeping each window but its last `window_overlap_m` (where its free end pulls the
  // costates to zero); the continuation then starts on the whole road from the stitched states
  // and costates (at a junction the previous window's costates, lambda_e and lambda_T carried
  // across it: window_stitch.h). From the QSS guess the first step's difficulty grows with the
  // road (docs/lap_log.md "The first step in windows"); the prototype's 60 km first step was solved this way
  // (../shared/notes/lap-solver-prototype.md). The windows' steps come first in
  // SolveSummary::steps (their lap times those of their windows alone) and their iterations
  // count in SolveSummary::iterations. A window counts as solved on its residuals alone: its
  // constraints are the whole road's to meet (docs/lap_log.md "A window's constraints").
  // 0 <= window_overlap_m < window_m, else SolveIndirect throws std::invalid_argument.
  double window_m = 0.0;
  double window_overlap_m = 1000.0;
  // The windows' homotopy_handoff. On the TT course (20 m, at most 0.5 s, 3 km windows) the first
  // 10 km took 788 iterations, 47.5 s, against 1,350, 69.4 s without (0.3: 741, 45.2 s; 3: 851,
  // 48.2 s; 10: 1,026, 57.8 s; 1 was the first value tried), the whole course 454.0 s against
  // 556.0 s (5,825 iterations against 7,991), the windows 244.1 s against 334.8 s.
  double window_homotopy_handoff = 1.0;
  // The windows do not stop at the first step: each follows the continuation down to this weight
  // (clamped to [eps_end, the first step's weight]; at that weight: the first step alone), and
  // the whole road's continuation starts there by Newton's homotopy from their stitched answer.
  // The steps that cost the most on the whole road are those of the first decade in eps (TT
  // course, 20 m: 41 of 73 arclength steps, 213 of 360 s), and a window takes them on its own
  // 3 km: the first 10 km 92.1 -> 53.8 s, the whole course 705.6 -> 634.0 s (docs/lap_log.md
  // "Windows down to eps 1e-2"). Below 1e-2 the whole road's homotopy from the stitched windows
  // did not converge (1e-4: a turning point in t, then Levenberg-Marquardt failed at a junction).
  // Where the whole road's first step from the windows fails, the windows are solved again down to
  // ten times this weight, at most their first step's (SolveFromWindows, indirect.cc): on the TT
  // course the grid's gear 4.0 with 30 MJ failed from 1e-2 and converged from 0.1 (docs/lap_log.md
  // "Session 55").
  double window_eps_end = 1e-2;
  // A window that fails every try is solved again from the same start as a window of half the
  // length (the same overlap), as long as that length is at least window_min_m [m] and longer
  // than the overlap; the next window has the full length again. On the TT course (3 km windows
  // at 20 m) the window at 40.0-43.0 km converged in 544 of 600 iterations in one run and failed
  // every try in the next, after a change that moved only rounding errors (docs/lap_log.md).
  double window_min_m = 1000.0;
  // A window's second guess, from its start state on its mesh (states and controls at its nodes,
  // x[0] the start state), tried when the window fails from the stitched guess (the previous
  // window's solution over the overlap, the road's guess beyond) and before the heavier weight;
  // empty: none. lap gives the QSS lap on the window's own racing line from the start state
  // (QssWindowGuess, lap/qss.h): on the TT course the window at 20-22.5 km failed from the
  // stitched guess and converges from that one (docs/lap_log.md "A guess for every window").
  WindowGuess window_guess;
  // A price on the charge left at the road's end [s/J]: the terminal cost -price e(s_end) added
  // to the lap time, so that the solve values a joule left in the pack at `price` seconds (0: the
  // lap's own free end, eq. 38). The windows set it at their free ends (below).
  double end_charge_price_s_per_j = 0.0;
  // The end_charge_price_s_per_j of every window but the last (0: none). A window's free end
  // spends the pack as if the rest of the lap needed no charge: on the TT course with
  // data/bx15.yaml's bike, whose lap is limited by its pack, the windows from 44.5 km on failed in
  // the charge's equations, and with 7 s/MJ at their ends every window converged (the whole
  // road's own lambda_e came to ~8.6 s/MJ; docs/lap_log.md "The charge's price at the windows'
  // ends"). lap gives the QSS lap's time per joule of the pack (QssChargePrice, lap/qss.h).
  double window_charge_price_s_per_j = 0.0;
  // Whether a solve from a guess without costates on a road of `length` metres takes its first
  // step in windows (window_m above).
  bool SolvesInWindows(double length) const { return window_m > 0.0 && length > window_m; }
  // The condition above on window_m and window_overlap_m.
  bool WindowsAreValid() const {
    return window_m <= 0.0 || (window_overlap_m >= 0.0 && window_overlap_m < window_m);
  }
  int num_threads = 2;           // for the node evaluations and Ceres
  bool verbose = false;          // Ceres' per-iteration log
};

// Solves from the initial guess (x, and lambda or zeros); x[0] is the fixed initial state.
LapSolution SolveIndirect(const Vehicle& v, const RoadTrack& road,
                          const std::vector<double>& mesh,
                          const std::vector<StateVector<double>>& x_guess,
                          const std::vector<StateVector<double>>& lambda_guess,
                          const std::vector<ControlVector<double>>& u_guess,
                          const IndirectOptions& options, SolveSummary* summary);

// From the solution in `tr` at the weight eps with the motor current's switch widened
// (IndirectOptions::current_widening) to the solution with the model's own switch, by Newton's
// homotopy at eps from there (as a first step's: IndirectOptions::homotopy); true when it got there (`tr` then solves
// the model's system, its current_widening 1), else the unknowns and the widening are back where
// they were. `step`: the homotopy as a continuation step at eps (its iterations, time and lap).
// SolveIndirect takes this way where the continuation with the widened switch stops above
// current_model_eps, and follows the continuation again with the model's switch from there.
bool ToModelSwitch(const IndirectOptions& options, Transcription* tr, double eps,
                   ContinuationStep* step);

// The lap time extrapolated linearly in eps to eps = 0 through the last converged step and the
// latest one before it at a weight at least 5 % larger (LapSolution::lap_time_extrapolated); the
// last step's lap time when there is none. Not simply the last two: a path that stops where its
// steps have shrunk can end on two weights 4.2e-9 apart (gear 4.2 in session 52, 9.8896443e-4
// and 9.8896022e-4), whose slope then rests on 9.3e-6 s of lap time. There it came out right
// (1711.922 s, Ipopt 1711.929 s), but an error of 1e-6 s in either lap would have moved it by
// 0.24 s; and after a turning point the last two need not be on one branch.
double ExtrapolateLapTime(const std::vector<ContinuationStep>& converged);

}  // namespace ttz::lap
