#include "lap/solver/indirect.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/log.h"
#include "lap/solver/node.h"
#include "lap/solver/transcription.h"

namespace ttz::lap {
namespace {

// Stops Ceres once the residual norm is below the tolerance.
class StopAtTolerance : public ceres::IterationCallback {
 public:
  explicit StopAtTolerance(double tol) : tol_(tol) {}
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
    if (s.step_is_successful)
      for (NodeData& d : tr_->mids) d.u_start = d.u;
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Transcription* tr_;
};

// The barrier weight eps with its relaxation delta = min(1e-3, 0.1 eps) (lap-solver notes).
BarrierWeight WeightFor(double eps) { return {eps, std::min(1e-3, 0.1 * eps)}; }

ceres::Solver::Options CeresOptions(const IndirectOptions& options) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
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

// The barrier continuation: solve at eps, shrink eps by the factor after a converged step, go
// back to the last converged step with a smaller factor after a failed one.
struct Continuation {
  std::vector<ContinuationStep> good;  // converged steps
  double max_all = HUGE_VAL, max_state = HUGE_VAL;  // residual levels of the last converged step
  double failed_eps = 0.0;             // > 0 when the continuation gave up there
};

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
    ceres::Solve(so, problem, &cs);
    double max_all, max_state;
    ResidualLevels(tr, &max_all, &max_state);
    ContinuationStep step;
    step.eps = eps;
    step.iterations = static_cast<int>(cs.iterations.size());
    step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    step.converged = tr->all_valid && max_all <= 10.0 * tolerance;
    step.lap_time = tr->all_valid ? tr->LapTime() : 0.0;
    summary->iterations += step.iterations;
    summary->steps.push_back(step);
    std::ostringstream o;
    o << "eps " << eps << ": " << (step.converged ? "converged" : "FAILED") << " in "
      << step.iterations << " iterations, " << step.seconds << " s, lap " << step.lap_time
      << " s, max residual " << max_all;
    if (!step.converged) o << " (" << cs.message << ")";
    Log(LogKind::kInfo, o.str());
    if (step.converged) {
      c.good.push_back(step);
      c.max_all = max_all;
      c.max_state = max_state;
      w_good = tr->w;
      mids_good = tr->mids;
      retries = 0;
      for (NodeData& d : tr->mids) d.u_start = d.u;
      if (last_step) break;
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
// (one per midpoint); the nodes report NodeControls of them (solution.h). Every constraint is checked where the transcription evaluates it, at the
// midpoints.
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
  sol.u = NodeControls(sol.u_interval);
  sol.lap_time = sol.t.back();
  return sol;
}

// Linear extrapolation of the lap time in eps through the last two converged steps to eps = 0.
double Extrapolate(const std::vector<ContinuationStep>& good) {
  if (good.size() < 2) return good.empty() ? 0.0 : good.back().lap_time;
  const ContinuationStep& a = good[good.size() - 2];
  const ContinuationStep& b = good.back();
  return b.lap_time - (a.lap_time - b.lap_time) * b.eps / (a.eps - b.eps);
}

// The honesty checks of the answer: why it is not converged, or "" when it is.
std::string Verdict(const IndirectOptions& options, const Continuation& c,
                    const SolveSummary& summary) {
  const double worst = *std::max_element(summary.max_violation.begin(),
                                         summary.max_violation.end());
  std::ostringstream why;
  if (c.failed_eps > 0.0) why << "continuation failed at eps " << c.failed_eps << "; ";
  if (!(c.max_all <= 10.0 * options.residual_tolerance)) why << "residual " << c.max_all << "; ";
  if (!(worst <= options.constraint_tolerance)) why << "constraint violated by " << worst << "; ";
  if (summary.control_failures > 0)
    why << summary.control_failures << " points without converged controls; ";
  return why.str();
}

}  // namespace

LapSolution SolveIndirect(const Vehicle& v, const RoadTrack& road,
                          const std::vector<double>& mesh,
                          const std::vector<StateVector<double>>& x_guess,
                          const std::vector<StateVector<double>>& lambda_guess,
                          const std::vector<ControlVector<double>>& u_guess,
                          const IndirectOptions& options, SolveSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  Transcription tr =
      MakeTranscription(v, road, mesh, x_guess, lambda_guess, u_guess, options.num_threads);
  ceres::Problem::Options popts;
  MidpointCallback callback(&tr);
  popts.evaluation_callback = &callback;
  ceres::Problem problem(popts);
  BuildProblem(&tr, &problem);

  summary->steps.clear();
  summary->iterations = 0;
  const Continuation c = RunContinuation(options, &tr, &problem, summary);
  if (!c.good.empty()) tr.weight = WeightFor(c.good.back().eps);
  LapSolution sol = NodeSolution(v, tr, summary);
  sol.eps = tr.weight.eps;
  sol.lap_time_extrapolated = c.good.empty() ? sol.lap_time : Extrapolate(c.good);
  summary->max_residual = c.max_all;
  summary->max_state_defect = c.max_state;
  summary->message = Verdict(options, c, *summary);
  summary->converged = summary->message.empty();
  summary->solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sol;
}

}  // namespace ttz::lap
