#include "lap/solver/indirect.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Sparse>

#include "common/log.h"
#include "lap/solver/node.h"
#include "lap/solver/solution_curve.h"
#include "lap/solver/sparse_lu.h"
#include "lap/solver/transcription.h"
#include "lap/solver/window_stitch.h"

namespace ttz::lap {
namespace {

// Stops Ceres once the residual norm is below the tolerance.
class StopAtTolerance : public ceres::IterationCallback {
 public:
  explicit StopAtTolerance(double tol) : tol_(tol) {}
  double tolerance() const { return tol_; }
  void set_tolerance(double tol) { tol_ = tol; }
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) final {
    return std::sqrt(2.0 * s.cost) <= tol_ ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                           : ceres::SOLVER_CONTINUE;
  }

 private:
  double tol_;
};

// After an accepted step, the controls found there become the Newton starts of the next ones.
class AcceptControls : public ceres::IterationCallback {
 public:
  explicit AcceptControls(Transcription* tr) : tr_(tr) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) final {
    if (s.step_is_successful) tr_->KeepControlsAsStarts();
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Transcription* tr_;
};

ceres::Solver::Options CeresOptions(const IndirectOptions& options) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's simplicial Cholesky rather than CHOLMOD's supernodal one: Debian's CHOLMOD hands each
  // factorisation to OpenMP threads, whose wake-ups cost more than they save on these block-banded
  // systems (docs/lap_log.md "Eigen's sparse Cholesky": first 10 km 55.1 -> 42.8 s).
  so.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = 1e-16;
  so.gradient_tolerance = 1e-30;
  so.parameter_tolerance = 1e-16;
  so.num_threads = options.num_threads;
  so.minimizer_progress_to_stdout = options.verbose;
  so.update_state_every_iteration = true;
  return so;
}

// The unknowns and the midpoints' controls of `tr` where a path starts, to go back to where it is
// given up on (with the controls as the Newton starts of the next solves).
class PathStart {
 public:
  explicit PathStart(const Transcription& tr) : w_(tr.w), mids_(tr.mids) {}
  void Restore(Transcription* tr) const {
    tr->w = w_;
    tr->mids = mids_;
    tr->KeepControlsAsStarts();
  }

 private:
  std::vector<double> w_;
  std::vector<NodeData> mids_;
};

// Newton iterations of a path with the bound on the correctors' contraction before it is followed
// again without it (TraceCurve): a bounded path may creep, its correctors stopped and its steps
// halved; the whole TT course's took 119 (docs/lap_log.md, session 51).
constexpr int kBoundedPathIterations = 400;

// Follows the barrier continuation's solution curve (BarrierPath) from the converged point in `tr`
// at eps0 down to eps_end (FollowPath); every point is appended to `steps` with its lap time. At a
// turning point of the curve (eps starts to grow: the points below it in eps are on another
// branch) `turning_point` says where on the road the solution turns. Where the path with the bound
// on the correctors' contraction (arclength_contraction_max) does not reach eps_end within
// kBoundedPathIterations (it turned, its steps shrank to nothing, or it crept), it is followed
// again from eps0 without the bound, so that the bound never ends a path higher than the path
// without it: on the TT course gear 4.2's bounded path stopped at eps 1.66e-3, its unbounded one
// at 9.7e-4 (docs/lap_log.md, session 51). `*last_from` is the index in `steps` where the last
// path's points start (0 without such a retry). True when eps_end was reached.
bool TraceCurve(const IndirectOptions& options, Transcription* tr, double eps0,
                std::vector<ContinuationStep>* steps, size_t* last_from, std::string* turning_point) {
  CurveSystem sys(tr);
  BarrierPath path(&sys);
  PathSettings settings;
  settings.p_end = std::log(options.eps_end);
  settings.first_dp = options.arclength_dlogeps;
  settings.tolerance = options.path_tolerance;
  settings.final_tolerance = 10.0 * options.residual_tolerance;
  settings.corrector_iterations = options.corrector_iterations;
  // Stalled correctors are not stopped on the barrier continuation: on the TT course's first 5 km
  // (5 m) that led to a turning point at eps 1.34e-4 that full correctors step over to converge
  // at eps_end (SnaefellOracleTest.First5kmAgreement; docs/lap_log.md "Stalled correctors").
  // Correctors that do not contract are (IndirectOptions::arclength_contraction_max), with the
  // path followed again without the bound where it does not reach eps_end.
  settings.stop_stalled = false;
  settings.max_contraction = options.arclength_contraction_max;
  settings.max_turn = options.arclength_max_turn_rad;
  const auto report = [&](const PathPoint& point) {
    ContinuationStep step;
    step.eps = point.last ? options.eps_end : std::exp(point.p);
    step.iterations = point.iterations;
    step.seconds = point.seconds;
    step.converged = point.Accepted();  // a step that turned too sharply is not on the path
    std::ostringstream o;
    o << "arclength eps " << step.eps << ": ";
    if (point.converged) {
      tr->weight = WeightFor(step.eps);
      tr->EvaluateMids(false);
      step.lap_time = tr->LapTime();
      o << "converged in " << step.iterations << " iterations, " << step.seconds << " s, lap "
        << step.lap_time << " s, max residual " << point.max_residual;
      if (!point.last)
        o << ", d log eps / ds " << point.slope << ", step " << point.length << ", turn "
          << point.turn << " rad";
      if (point.too_sharp) o << " > " << settings.max_turn << ": retried shorter";
    } else {  // where its last iterate's largest residual sits (FollowPath has not reset it yet)
      double max_all, max_state;
      ResidualPeak peak;
      ResidualLevels(tr, &max_all, &max_state, &peak);
      o << "FAILED in " << step.iterations << " iterations, " << step.seconds
        << " s, max residual " << point.max_residual << " (" << max_all << " at " << DescribePeak(*tr, peak)
        << "), step " << point.length;
    }
    Log(LogKind::kInfo, o.str());
    steps->push_back(step);
  };
  const PathStart start(*tr);
  const bool bounded = std::isfinite(settings.max_contraction);
  if (bounded) settings.max_iterations = kBoundedPathIterations;
  Eigen::VectorXd turn;
  *last_from = 0;
  PathEnd end = FollowPath(&sys, &path, std::log(eps0), settings, report, &turn);
  if (bounded && end != PathEnd::kReached) {
    // A stopped corrector shortens the step, and a shorter step may follow the curve into a
    // turning point that a full corrector steps over (docs/lap_log.md, session 51).
    std::ostringstream o;
    o << "arclength: again from eps " << eps0 << " without the bound on the correctors' contraction";
    Log(LogKind::kInfo, o.str());
    start.Restore(tr);
    settings.max_contraction = std::numeric_limits<double>::infinity();
    settings.max_iterations = std::numeric_limits<int>::max();
    *last_from = steps->size();
    end = FollowPath(&sys, &path, std::log(eps0), settings, report, &turn);
  }
  if (end == PathEnd::kTurned) {
    *turning_point = sys.DescribeStateDirection(turn);
    Log(LogKind::kInfo, "arclength: turning point of the solution curve at eps " +
                            std::to_string(steps->back().eps) + ": " + *turning_point);
  }
  return end == PathEnd::kReached;
}

// Follows `family` (its parameter `name` in the log) from its solution in `tr` at p = 0 to p = 1,
// where it is F = 0 at eps, to residual_tolerance; true when it got there. Otherwise (a turning
// point in p, a failed step, the iterations of max_iterations spent) the unknowns and the
// controls' Newton starts are back at the start. `iterations`: Newton's.
bool FollowFromStart(const IndirectOptions& options, CurveSystem* sys, PathFamily* family,
                     const char* name, int* iterations) {
  Transcription* tr = sys->transcription();
  const PathStart start(*tr);
  PathSettings settings;
  settings.p_end = 1.0;
  settings.first_dp = 0.1;
  settings.tolerance = options.homotopy_tolerance;
  settings.final_tolerance = 10.0 * options.residual_tolerance;
  settings.corrector_iterations = options.corrector_iterations;
  settings.max_contraction = options.corrector_contraction_max;
  settings.max_iterations = options.max_iterations;
  const auto report = [&](const PathPoint& point) {
    *iterations += point.iterations;
    std::ostringstream o;
    o << name << " " << point.p << ": " << (point.converged ? "converged" : "FAILED") << " in "
      << point.iterations << " iterations, " << point.seconds << " s, max residual "
      << point.max_residual;
    Log(LogKind::kInfo, o.str());
  };
  Eigen::VectorXd turn;
  const PathEnd end = FollowPath(sys, family, 0.0, settings, report, &turn);
  if (end == PathEnd::kReached) return true;
  Log(LogKind::kInfo, std::string(name) +
                          (end == PathEnd::kTurned ? ": a turning point" : ": failed") +
                          "; back to its start");
  start.Restore(tr);
  return false;
}

// The first step at eps from a start near its solution (IndirectOptions::homotopy) by Newton's
// homotopy (NewtonHomotopy) from t = 0 to 1 (FollowFromStart); true when it reached F = 0, or when
// the start solves F already.
bool FirstStepByHomotopy(const IndirectOptions& options, Transcription* tr, double eps,
                         int* iterations) {
  CurveSystem sys(tr);
  NewtonHomotopy homotopy(&sys, eps);
  *iterations = 0;
  if (!homotopy.Start()) return false;
  if (homotopy.r0().lpNorm<Eigen::Infinity>() <= 10.0 * options.residual_tolerance) return true;
  return FollowFromStart(options, &sys, &homotopy, "homotopy t", iterations);
}

// The first step's solve at eps to the tolerance of `stop`; its iterations, Levenberg-Marquardt's
// and Newton's, and in `cs` LM's last summary (empty when it did not run). Newton's homotopy
// (FirstStepByHomotopy) starts at a start near its solution (node barriers on) and, from a guess,
// where LM first has ||F|| <= IndirectOptions::homotopy_handoff; where it fails LM goes on from
// the homotopy's start (where LM stopped, with its trust-region radius).
int SolveFirstStep(const IndirectOptions& options, double eps, Transcription* tr,
                   ceres::Problem* problem, const ceres::Solver::Options& so,
                   StopAtTolerance* stop, ceres::Solver::Summary* cs) {
  int iterations = 0;
  ceres::Solver::Options lm = so;  // LM goes on where it stopped, within so.max_num_iterations
  bool near = tr->node_barriers;
  if (options.homotopy && !near && options.homotopy_handoff > 0.0) {
    const double tolerance = stop->tolerance();
    stop->set_tolerance(options.homotopy_handoff);
    ceres::Solve(lm, problem, cs);
    stop->set_tolerance(tolerance);
    iterations = static_cast<int>(cs->iterations.size());
    lm.max_num_iterations = std::max(1, so.max_num_iterations - iterations);
    if (!cs->iterations.empty())
      lm.initial_trust_region_radius = cs->iterations.back().trust_region_radius;
    const double norm = std::sqrt(2.0 * cs->final_cost);  // ||F||_2, as StopAtTolerance's
    near = norm <= options.homotopy_handoff;
    if (!near) return iterations;  // LM stopped short of the handoff: its answer stands
    std::ostringstream o;
    o << "Levenberg-Marquardt at ||F|| " << norm << " after "
      << iterations << " iterations: Newton's homotopy from there";
    Log(LogKind::kInfo, o.str());
  }
  if (options.homotopy && near) {
    int homotopy_iterations = 0;
    const bool reached = FirstStepByHomotopy(options, tr, eps, &homotopy_iterations);
    iterations += homotopy_iterations;
    *cs = ceres::Solver::Summary();
    if (reached) return iterations;
  }
  ceres::Solve(lm, problem, cs);
  return iterations + static_cast<int>(cs->iterations.size());
}

// The node barriers switched on at eps (the weight of the midpoints' solution in `tr`) by the
// continuation in their share of eps (NodeBarrierPath) from 0 to 1; true when it got there, else
// the unknowns are back at the midpoints' solution. Either way the share is 1 after it.
bool SwitchOnNodeBarriers(const IndirectOptions& options, Transcription* tr, double eps,
                          int* iterations) {
  CurveSystem sys(tr);
  NodeBarrierPath path(&sys, eps);
  *iterations = 0;
  tr->node_share = 0.0;
  const bool reached = FollowFromStart(options, &sys, &path, "node barriers' share", iterations);
  tr->node_share = 1.0;
  return reached;
}

// The barrier continuation: solve at eps, shrink eps by the factor after a converged step, go
// back to the last converged step with a smaller factor after a failed one.
struct Continuation {
  std::vector<ContinuationStep> good;  // converged steps
  double max_all = HUGE_VAL, max_state = HUGE_VAL;  // residual levels of the last converged step
  double failed_eps = 0.0;             // > 0 when the continuation gave up there
  std::string turning_point;           // where the solution turned, when it stopped at a turn
  std::string near_singular;           // where J is nearly singular, when it stopped otherwise
  double below_end_stopped_eps = 0.0;  // > 0 when the curve below eps_end stopped there
};

// Follows the solution curve (TraceCurve) from the last converged step of `c` down to
// options.eps_end, appending its points to `summary` and the converged ones of its last path (not
// those of a bounded one given up on: TraceCurve) to `c` (ExtrapolateLapTime's steps);
// the unknowns stay at its last converged point, whose residual levels (those of the path's
// tolerance, or the final one at eps_end) become c's. Where a path with the motor current's switch
// widened (IndirectOptions::current_widening) stops at a weight where it is widened, the path is
// followed again from eps0 with the model's switch (ToModelSwitch), whose points are then the last
// path's: on the TT course gear 4.1 stopped at eps 1.43e-3 with the widening and converged
// without it (docs/lap_log.md "Session 54: a wider switch while the barrier is heavy"). 0 when
// eps_end was reached, else the weight where the curve stopped (failed or turned).
double FollowCurve(const IndirectOptions& options, Transcription* tr, Continuation* c,
                   SolveSummary* summary) {
  const double eps0 = c->good.back().eps;
  const PathStart start(*tr);
  std::vector<ContinuationStep> curve;
  size_t last_from = 0;  // a path given up on and followed again: only the last one's points count
  bool reached = TraceCurve(options, tr, eps0, &curve, &last_from, &c->turning_point);
  double stopped = curve.empty() ? eps0 : curve.back().eps;
  if (!reached && tr->current_widening > 1.0 && stopped > tr->current_model_eps) {
    // It stopped where the switch is widened: again from eps0 with the model's own switch.
    std::ostringstream o;
    o << "arclength: stopped at eps " << stopped
      << " with the motor current's switch widened: again from eps " << eps0 << " with the model's";
    Log(LogKind::kInfo, o.str());
    const PathStart stop(*tr);
    start.Restore(tr);
    ContinuationStep to_model;
    if (ToModelSwitch(options, tr, eps0, &to_model)) {
      std::vector<ContinuationStep> again{to_model};
      size_t again_from = 0;
      c->turning_point.clear();
      reached = TraceCurve(options, tr, eps0, &again, &again_from, &c->turning_point);
      last_from = curve.size() + again_from;
      curve.insert(curve.end(), again.begin(), again.end());
      stopped = curve.back().eps;
    } else {  // the widened path's end stands
      stop.Restore(tr);
      curve.push_back(to_model);
    }
  }
  for (size_t i = 0; i < curve.size(); ++i) {
    summary->iterations += curve[i].iterations;
    summary->steps.push_back(curve[i]);
    if (curve[i].converged && i >= last_from) c->good.push_back(curve[i]);
  }
  tr->weight = WeightFor(c->good.back().eps);
  ResidualLevels(tr, &c->max_all, &c->max_state);
  return reached ? 0.0 : stopped;
}

Continuation RunContinuation(const IndirectOptions& options, Transcription* tr,
                             ceres::Problem* problem, SolveSummary* summary) {
  ceres::Solver::Options so = CeresOptions(options);
  AcceptControls accept(tr);
  StopAtTolerance stop(options.residual_tolerance);
  so.callbacks = {&accept, &stop};
  Continuation c;
  double eps = options.eps_start, factor = options.eps_factor;
  std::vector<double> w_good = tr->w;
  std::vector<NodeData> mids_good = tr->mids;
  int retries = 0;
  while (true) {
    const bool first = c.good.empty();
    const bool last_step = eps <= options.eps_end * (1 + 1e-12);
    // The path between the first and the last step need not be exact.
    const double tolerance =
        first || last_step ? options.residual_tolerance : options.path_tolerance;
    stop.set_tolerance(tolerance);
    tr->weight = WeightFor(eps);
    so.use_nonmonotonic_steps = first;
    so.max_num_iterations = first ? options.max_iterations : options.max_step_iterations;
    so.initial_trust_region_radius = first ? 1e4 : 1e12;
    ceres::Solver::Summary cs;
    const auto t0 = std::chrono::steady_clock::now();
    int iterations = 0;
    if (first) {
      iterations = SolveFirstStep(options, eps, tr, problem, so, &stop, &cs);
    } else {
      ceres::Solve(so, problem, &cs);
      iterations = static_cast<int>(cs.iterations.size());
    }
    double max_all, max_state;
    ResidualPeak peak;
    ResidualLevels(tr, &max_all, &max_state, &peak);
    ContinuationStep step;
    step.eps = eps;
    step.iterations = iterations;
    step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    step.converged = tr->all_valid && max_all <= 10.0 * tolerance;
    step.lap_time = tr->all_valid ? tr->LapTime() : 0.0;
    summary->iterations += step.iterations;
    summary->steps.push_back(step);
    std::ostringstream o;
    o << "eps " << eps << ": " << (step.converged ? "converged" : "FAILED") << " in "
      << step.iterations << " iterations, " << step.seconds << " s, lap " << step.lap_time
      << " s, max residual " << max_all;
    if (!step.converged) o << " at " << DescribePeak(*tr, peak) << " (" << cs.message << ")";
    Log(LogKind::kInfo, o.str());
    if (step.converged) {
      c.good.push_back(step);
      c.max_all = max_all;
      c.max_state = max_state;
      w_good = tr->w;
      mids_good = tr->mids;
      retries = 0;
      tr->KeepControlsAsStarts();
      if (last_step) break;
      if (options.arclength) {  // the rest of the way along the curve
        c.failed_eps = FollowCurve(options, tr, &c, summary);
        w_good = tr->w;
        mids_good = tr->mids;
        break;
      }
      factor = std::max(options.eps_factor, factor * factor);  // back towards the full step
      eps = std::max(options.eps_end, eps * factor);
      continue;
    }
    if (first || ++retries > options.max_retries) {
      c.failed_eps = eps;
      break;
    }
    tr->w = w_good;
    tr->mids = mids_good;
    const double last = c.good.back().eps;
    factor = std::sqrt(eps / last);
    eps = last * factor;
  }
  if (!c.good.empty()) {  // else keep the last iterate of the failed first solve: it shows where
    tr->w = w_good;       // the solve got stuck
    tr->mids = mids_good;
  }
  return c;
}

// States, costates and time at the nodes. The transcription's controls live on the intervals
// (one per midpoint); the nodes report NodeControls of them (solution.h). Every constraint is
// checked where the transcription has its barrier: at the midpoints, and with node barriers at
// the nodes 1..N.
LapSolution NodeSolution(const Vehicle& v, const Transcription& tr, SolveSummary* summary) {
  const int n = tr.NumNodes();
  LapSolution sol;
  sol.s = tr.s;
  sol.x.resize(n);
  sol.lambda.resize(n);
  sol.u_interval.resize(n - 1);
  sol.t.assign(n, 0.0);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < kNumStates; ++i) {
      sol.x[k][i] = tr.w[k * kW + i] * tr.sc.state[i];
      sol.lambda[k][i] = tr.w[k * kW + kNumStates + i];
    }
  summary->max_violation.assign(kNumConstraints, -HUGE_VAL);
  summary->control_failures = 0;
  for (int k = 0; k + 1 < n; ++k) {
    const NodeData& mid = tr.mids[k];
    sol.t[k + 1] = sol.t[k] + tr.H(k) * mid.dt_ds;
    if (!mid.control_converged) ++summary->control_failures;
    StateVector<double> xm;
    ControlVector<double> um;
    for (int i = 0; i < kNumStates; ++i) xm[i] = 0.5 * (sol.x[k][i] + sol.x[k + 1][i]);
    for (int i = 0; i < kNumControls; ++i) um[i] = mid.u[i] * tr.sc.control[i];
    sol.u_interval[k] = um;
    const RoadPoint& rp = tr.road[k];
    const ConstraintVector<double> g = EvaluateConstraints(v, xm, um, rp, EvaluateModel(v, xm, um, rp));
    for (int j = 0; j < kNumConstraints; ++j)
      summary->max_violation[j] = std::max(summary->max_violation[j], g[j]);
  }
  for (int k = 1; k < n && tr.node_barriers; ++k) {
    const ConstraintVector<double> g = StateConstraints(v, sol.x[k], tr.road_nodes[k]);
    for (int j = 0; j < kNumConstraints; ++j)
      summary->max_violation[j] = std::max(summary->max_violation[j], g[j]);
  }
  sol.u = NodeControls(sol.u_interval);
  sol.lap_time = sol.t.back();
  return sol;
}

// The largest relative violation g_j of the answer's constraints (> 0: violated).
double WorstViolation(const SolveSummary& summary) {
  return *std::max_element(summary.max_violation.begin(), summary.max_violation.end());
}

// Below eps_end (IndirectOptions::eps_floor): while the answer of a continuation that reached its
// end violates a constraint by more than constraint_tolerance, the curve is followed on down to
// half the weight, to at most eps_floor; `sol` and the summary's violations are then those of its
// last converged point. Stops at the first stretch that does not reach its end: the answer stays
// at that stretch's last converged point, and the checks judge it.
void FollowBelowEpsEnd(const IndirectOptions& options, const Vehicle& v, Transcription* tr,
                       Continuation* c, SolveSummary* summary, LapSolution* sol) {
  while (c->failed_eps == 0.0 && !c->good.empty() &&
         WorstViolation(*summary) > options.constraint_tolerance &&
         c->good.back().eps > options.eps_floor * (1 + 1e-12)) {
    IndirectOptions deeper = options;
    deeper.eps_end = std::max(options.eps_floor, 0.5 * c->good.back().eps);
    std::ostringstream o;
    o << "a constraint violated by " << WorstViolation(*summary) << " at eps "
      << c->good.back().eps << ": the continuation goes on to eps " << deeper.eps_end;
    Log(LogKind::kInfo, o.str());
    c->below_end_stopped_eps = FollowCurve(deeper, tr, c, summary);
    *sol = NodeSolution(v, *tr, summary);
    if (c->below_end_stopped_eps > 0.0) return;
  }
}

// Where the Jacobian at the unknowns in `tr` and weight eps is nearly singular: |J x| and the
// states that the unit vector x of NearNullVector moves, "" when it is not found. At the gear
// study's five stops of session 52 on the TT course x lay in the wheel torque or the roll rate on
// 200-430 m of road, on the converged reference lap in the lateral position along half of it
// (docs/lap_log.md "Session 52"). Also run where a window of the first step fails (SolveWindow),
// whose log line then says it: one LU of the window's J and ten solves.
std::string NearSingularDirection(Transcription* tr, double eps) {
  CurveSystem sys(tr);
  Eigen::VectorXd F, x;
  Eigen::SparseMatrix<double> J;
  double shrunk = 0.0;
  if (!sys.Evaluate(eps, &F, &J, nullptr) ||
      !NearNullVector(J, CurveSystem::kJacobianForm, kNearNullIterations, &x, &shrunk))
    return "";
  std::ostringstream o;
  o << "|J x| = " << shrunk << " for the unit x of inverse iteration; " << sys.DescribeStateDirection(x);
  return o.str();
}

// The honesty checks of the answer: why it is not converged, or "" when it is.
std::string Verdict(const IndirectOptions& options, const Continuation& c,
                    const SolveSummary& summary) {
  const double worst = WorstViolation(summary);
  std::ostringstream why;
  if (c.failed_eps > 0.0) {
    why << "continuation failed at eps " << c.failed_eps;
    if (!c.turning_point.empty()) why << " (a turning point: " << c.turning_point << ")";
    else if (!c.near_singular.empty()) why << " (its Jacobian nearly singular: " << c.near_singular << ")";
    why << "; ";
  }
  if (c.below_end_stopped_eps > 0.0)
    why << "the continuation below eps_end, for the constraints, stopped at eps "
        << c.below_end_stopped_eps << "; ";
  if (!(c.max_all <= 10.0 * options.residual_tolerance)) why << "residual " << c.max_all << "; ";
  if (!(worst <= options.constraint_tolerance)) why << "constraint violated by " << worst << "; ";
  if (summary.control_failures > 0)
    why << summary.control_failures << " points without converged controls; ";
  return why.str();
}

// The continuation from the unknowns in `tr`. From a guess without costates the first solve is of
// the midpoints' barriers alone: the quasi-steady guess sits on its limits, where a node barrier's
// gradient is 2 / delta, and as a jump of the costates between two midpoints it would drive the
// first solve's controls far off (the midpoints see it spread over an interval). The continuation
// proper starts from that answer; without one it does not start.
Continuation SolveFrom(const IndirectOptions& options, bool from_guess, Transcription* tr,
                       ceres::Problem* problem, SolveSummary* summary) {
  if (tr->node_barriers && from_guess) {
    IndirectOptions midpoints = options;
    midpoints.eps_end = options.eps_start;
    tr->node_barriers = false;
    const Continuation first = RunContinuation(midpoints, tr, problem, summary);
    tr->node_barriers = true;
    if (first.good.empty()) return first;
    int iterations = 0;
    if (options.node_share_path)
      SwitchOnNodeBarriers(options, tr, first.good.back().eps, &iterations);
    summary->iterations += iterations;
  }
  return RunContinuation(options, tr, problem, summary);
}

// The weight down to which the windows follow the continuation (IndirectOptions::window_eps_end),
// where the whole road's starts.
double WindowsEpsEnd(const IndirectOptions& options) {
  return std::min(options.eps_start, std::max(options.window_eps_end, options.eps_end));
}

// Window [a, b] by its tries, each from eps_start (a ten times heavier barrier in the last) down to
// the window's eps_end: from the stitched guess, from its own guess
// (IndirectOptions::window_guess, when given), from the stitched guess under the heavier barrier
// (docs/lap_log.md "A price on rolling the bike"); true when one converged, with its answer in `sol`.
bool SolveWindow(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh, int a,
                 int b, const IndirectOptions& window,
                 const std::vector<StateVector<double>>& x_guess,
                 const std::vector<ControlVector<double>>& u_guess, LapSolution* sol,
                 SolveSummary* summary) {
  IndirectOptions heavier = window;
  heavier.eps_start = 10.0 * window.eps_start;
  const std::vector<double> sub_mesh(mesh.begin() + a, mesh.begin() + b + 1);
  const std::vector<StateVector<double>> sub_x(x_guess.begin() + a, x_guess.begin() + b + 1);
  const std::vector<ControlVector<double>> sub_u(u_guess.begin() + a, u_guess.begin() + b + 1);
  std::vector<StateVector<double>> own_x;
  std::vector<ControlVector<double>> own_u;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const bool own = attempt == 1;
    if (own && !window.window_guess) continue;
    if (own) window.window_guess(sub_x.front(), sub_mesh, &own_x, &own_u);
    const IndirectOptions& o = attempt == 2 ? heavier : window;
    SolveSummary ws;
    *sol = SolveIndirect(v, road, sub_mesh, own ? own_x : sub_x, {}, own ? own_u : sub_u, o, &ws);
    summary->iterations += ws.iterations;
    summary->steps.insert(summary->steps.end(), ws.steps.begin(), ws.steps.end());
    std::ostringstream line;
    line << "window " << mesh[a] << " - " << mesh[b] << " m from "
         << (own ? "its own" : "the stitched") << " guess at eps " << o.eps_start << ": "
         << (ws.converged ? "converged" : "FAILED") << " in " << ws.iterations << " iterations, "
         << ws.solve_seconds << " s";
    if (!ws.converged) line << " (" << SolveMessage(ws) << ")";
    Log(LogKind::kInfo, line.str());
    if (ws.converged) return true;
  }
  return false;
}

// The first step, and the continuation down to WindowsEpsEnd, window by window
// (IndirectOptions::window_m): fills lambda_guess and updates x_guess and u_guess with the
// stitched windows' solution; false when a window failed (at every length down to window_min_m).
bool SolveFirstStepInWindows(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh, const IndirectOptions& options,
                             std::vector<StateVector<double>>* x_guess,
                             std::vector<StateVector<double>>* lambda_guess,
                             std::vector<ControlVector<double>>* u_guess, SolveSummary* summary) {
  const int n = static_cast<int>(mesh.size());
  lambda_guess->assign(n, StateVector<double>{});
  IndirectOptions window = options;
  window.window_m = 0.0;
  window.eps_end = WindowsEpsEnd(options);
  window.retry_eps_start = 0.0;
  window.homotopy_handoff = options.window_homotopy_handoff;
  // A window's answer is the whole road's start at window_eps_end, not an answer: its relaxed
  // barriers there may leave a constraint over by more than the answer's tolerance, which the
  // whole road's continuation down to eps_end takes back. So a window needs its residuals alone
  // (on the TT course with data/bx15.yaml's 600 A, the window from 20 km converged on every try
  // and was rejected for 3.7e-4 over: docs/lap_log.md "A window's constraints").
  window.constraint_tolerance = HUGE_VAL;
  std::vector<WindowJunction> junctions;
  double length = options.window_m;
  for (int a = 0;;) {
    int b = a;
    while (b + 1 < n && mesh[b] < mesh[a] + length) ++b;
    const bool last = b + 1 == n;
    window.end_charge_price_s_per_j = last ? 0.0 : options.window_charge_price_s_per_j;
    LapSolution sol;
    if (!SolveWindow(v, road, mesh, a, b, window, *x_guess, *u_guess, &sol, summary)) {
      length *= 0.5;  // a shorter window from the same start, with the same overlap
      if (length < options.window_min_m || length <= options.window_overlap_m) return false;
      std::ostringstream line;
      line << "window from " << mesh[a] << " m: again as " << length << " m";
      Log(LogKind::kInfo, line.str());
      continue;
    }
    if (a > 0) {  // the costates' jump where this window starts (window_stitch.h)
      WindowJunction j{a, {}};
      for (int i = 0; i < kNumStates; ++i) j.jump[i] = sol.lambda.front()[i] - (*lambda_guess)[a][i];
      junctions.push_back(j);
    }
    int keep = b;
    while (!last && keep > a + 1 && mesh[keep] > mesh[b] - options.window_overlap_m) --keep;
    // The whole window, overlap included: the next window solves the overlap again from this
    // window's states and controls there, which hold the start state it gets at mesh[keep],
    // rather than from the guess.
    // At its first node a window has no barrier (its state is fixed there), so its costates are
    // the right limits where the whole road's unknowns are the means of both limits
    // (transcription.h): the previous window's costates, for which the node is an inner one, stay.
    for (int k = a; k <= b; ++k) {
      (*x_guess)[k] = sol.x[k - a];
      if (k > a || a == 0) (*lambda_guess)[k] = sol.lambda[k - a];
      (*u_guess)[k] = sol.u[k - a];
    }
    if (last) {
      CarrySlowCostatesUpstream(junctions, lambda_guess);
      return true;
    }
    a = keep;
    length = options.window_m;
  }
}

// The first step in windows (SolveFirstStepInWindows, at retry_eps_start when that is set and
// smaller than eps_start), then the whole road's continuation from their stitched answer; from the
// guess when a window failed. Where the whole road's first step from the windows fails, the windows
// are solved again down to a ten times heavier weight (at most their first step's) and the whole
// road starts there: on the TT course the grid's gear 4.0 with a 30 MJ pack failed its first step
// from windows at eps 1e-2 (Newton's homotopy turned, Levenberg-Marquardt did not converge) and
// converged from windows at 0.1 (docs/lap_log.md "Session 55"). The summary's steps and
// iterations are those of every try, windows first; the rest that of the last whole-road solve.
LapSolution SolveFromWindows(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh,
                             const std::vector<StateVector<double>>& x_guess,
                             const std::vector<ControlVector<double>>& u_guess,
                             const IndirectOptions& options, SolveSummary* summary) {
  IndirectOptions windowed = options;  // the first step at the retry's weight (indirect.h)
  if (options.retry_eps_start > 0.0 && options.retry_eps_start < options.eps_start) {
    windowed.eps_start = options.retry_eps_start;
    windowed.retry_eps_start = 0.0;
  }
  std::vector<ContinuationStep> steps;
  int iterations = 0;
  for (;;) {
    std::vector<StateVector<double>> x = x_guess, lambda;
    std::vector<ControlVector<double>> u = u_guess;
    SolveSummary windows;
    const bool ok = SolveFirstStepInWindows(v, road, mesh, windowed, &x, &lambda, &u, &windows);
    IndirectOptions whole = ok ? windowed : options;
    whole.window_m = 0.0;
    if (ok) whole.eps_start = WindowsEpsEnd(windowed);
    if (!ok) Log(LogKind::kInfo, "a window of the first step failed: the whole road from the guess");
    LapSolution sol = ok ? SolveIndirect(v, road, mesh, x, lambda, u, whole, summary)
                         : SolveIndirect(v, road, mesh, x_guess, {}, u_guess, whole, summary);
    summary->first_step_in_windows = ok;
    steps.insert(steps.end(), windows.steps.begin(), windows.steps.end());
    steps.insert(steps.end(), summary->steps.begin(), summary->steps.end());
    iterations += windows.iterations + summary->iterations;
    const bool first_step_failed =
        std::none_of(summary->steps.begin(), summary->steps.end(),
                     [](const ContinuationStep& step) { return step.converged; });
    const double heavier = 10.0 * whole.eps_start;
    if (!ok || !first_step_failed || heavier > windowed.eps_start * (1.0 + 1e-12)) {
      if (!ok && !summary->message.empty()) summary->message = "a window failed; " + summary->message;
      summary->steps = steps;
      summary->iterations = iterations;
      return sol;
    }
    std::ostringstream o;
    o << "the whole road's first step from its windows at eps " << whole.eps_start
      << " failed: the windows again, down to eps " << heavier;
    Log(LogKind::kInfo, o.str());
    windowed.window_eps_end = heavier;
  }
}

}  // namespace

LapSolution SolveIndirect(const Vehicle& v, const RoadTrack& road,
                          const std::vector<double>& mesh,
                          const std::vector<StateVector<double>>& x_guess,
                          const std::vector<StateVector<double>>& lambda_guess,
                          const std::vector<ControlVector<double>>& u_guess,
                          const IndirectOptions& options, SolveSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.WindowsAreValid())
    throw std::invalid_argument("IndirectOptions: window_overlap_m must lie in [0, window_m)");
  if (lambda_guess.empty() && options.SolvesInWindows(mesh.back() - mesh.front())) {
    LapSolution sol = SolveFromWindows(v, road, mesh, x_guess, u_guess, options, summary);
    summary->solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return sol;
  }
  Transcription tr =
      MakeTranscription(v, road, mesh, x_guess, lambda_guess, u_guess, options.num_threads,
                        options.node_constraints);
  tr.end_charge_price = options.end_charge_price_s_per_j;
  tr.current_widening = options.current_widening;
  tr.current_model_eps = options.current_model_eps;
  ceres::Problem::Options popts;
  MidpointCallback callback(&tr);
  popts.evaluation_callback = &callback;
  ceres::Problem problem(popts);
  BuildProblem(&tr, &problem);

  summary->steps.clear();
  summary->iterations = 0;
  const bool from_guess = lambda_guess.empty();
  const std::vector<double> w_guess = tr.w;
  const std::vector<NodeData> mids_guess = tr.mids;
  Continuation c = SolveFrom(options, from_guess, &tr, &problem, summary);
  std::ostringstream retried;
  if (c.good.empty() && options.retry_eps_start > 0.0 &&
      options.retry_eps_start < options.eps_start) {
    retried << "first step failed at eps " << options.eps_start << ", retried from the guess; ";
    std::ostringstream o;
    o << "the first step at eps " << options.eps_start << " failed: again from the guess at eps "
      << options.retry_eps_start;
    Log(LogKind::kInfo, o.str());
    tr.w = w_guess;
    tr.mids = mids_guess;
    IndirectOptions retry = options;
    retry.eps_start = options.retry_eps_start;
    c = SolveFrom(retry, from_guess, &tr, &problem, summary);
  }
  if (!c.good.empty()) tr.weight = WeightFor(c.good.back().eps);
  LapSolution sol = NodeSolution(v, tr, summary);
  FollowBelowEpsEnd(options, v, &tr, &c, summary, &sol);
  if (c.failed_eps > 0.0 && c.turning_point.empty() && !c.good.empty())
    c.near_singular = NearSingularDirection(&tr, c.good.back().eps);
  sol.eps = tr.weight.eps;
  sol.lap_time_extrapolated = c.good.empty() ? sol.lap_time : ExtrapolateLapTime(c.good);
  summary->max_residual = c.max_all;
  summary->max_state_defect = c.max_state;
  summary->message = Verdict(options, c, *summary);
  if (!summary->message.empty()) summary->message = retried.str() + summary->message;
  summary->converged = summary->message.empty();
  summary->solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sol;
}

double ExtrapolateLapTime(const std::vector<ContinuationStep>& converged) {
  if (converged.empty()) return 0.0;
  const ContinuationStep& b = converged.back();
  for (auto a = converged.rbegin() + 1; a != converged.rend(); ++a)
    if (a->eps >= 1.05 * b.eps) return b.lap_time - (a->lap_time - b.lap_time) * b.eps / (a->eps - b.eps);
  return b.lap_time;
}

bool ToModelSwitch(const IndirectOptions& options, Transcription* tr, double eps,
                   ContinuationStep* step) {
  const auto t0 = std::chrono::steady_clock::now();
  const double widening = tr->current_widening;
  tr->current_widening = 1.0;
  step->eps = eps;
  step->converged = FirstStepByHomotopy(options, tr, eps, &step->iterations);
  step->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!step->converged) {
    tr->current_widening = widening;
    Log(LogKind::kInfo, "to the model's switch at eps " + std::to_string(eps) + ": FAILED");
    return false;
  }
  tr->weight = WeightFor(eps);
  tr->EvaluateMids(false);
  step->lap_time = tr->LapTime();
  std::ostringstream o;
  o << "to the model's switch at eps " << eps << ": converged in " << step->iterations
    << " iterations, " << step->seconds << " s, lap " << step->lap_time << " s";
  Log(LogKind::kInfo, o.str());
  return true;
}

}  // namespace ttz::lap
