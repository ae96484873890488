#include "lap/solver/indirect.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <thread>

#include "common/log.h"
#include "lap/solver/node.h"

namespace ttz::lap {
namespace {

constexpr int kW = 2 * kNumStates;  // unknowns per node: scaled states and costates

// The discretised necessary conditions: unknowns, node evaluations and the barrier weight.
struct Transcription {
  const Vehicle* v;
  Scales sc;
  std::vector<RoadPoint> road;
  std::vector<double> s;
  std::vector<double> w;  // (N + 1) x kW: [x~_k, lambda~_k]
  std::vector<NodeData> nodes;
  BarrierWeight weight{};  // set by the continuation before each solve
  int threads = 1;
  bool all_valid = false;

  int NumNodes() const { return static_cast<int>(s.size()); }
  double* W(int k) { return w.data() + k * kW; }

  void EvaluateNodes(bool jacobians) {
    auto work = [&](int first, int last) {
      for (int k = first; k < last; ++k) {
        StateVector<double> xs, ls;
        std::copy(W(k), W(k) + kNumStates, xs.begin());
        std::copy(W(k) + kNumStates, W(k) + kW, ls.begin());
        EvaluateNode(*v, sc, road[k], weight, xs, ls, jacobians, &nodes[k]);
      }
    };
    const int n = NumNodes(), parts = std::max(1, threads);
    std::vector<std::thread> pool;
    for (int p = 1; p < parts; ++p) pool.emplace_back(work, n * p / parts, n * (p + 1) / parts);
    work(0, n / parts);
    for (auto& t : pool) t.join();
    all_valid = std::all_of(nodes.begin(), nodes.end(), [](const NodeData& d) { return d.valid; });
  }

  double LapTime() const {
    double t = 0.0;
    for (int k = 0; k + 1 < NumNodes(); ++k)
      t += 0.5 * (s[k + 1] - s[k]) * (nodes[k].dt_ds + nodes[k + 1].dt_ds);
    return t;
  }
};

// Ceres calls this before evaluating residuals at a new point: every node is evaluated once.
class NodeCallback : public ceres::EvaluationCallback {
 public:
  explicit NodeCallback(Transcription* tr) : tr_(tr) {}
  void PrepareForEvaluation(bool evaluate_jacobians, bool) final {
    tr_->EvaluateNodes(evaluate_jacobians);
  }

 private:
  Transcription* tr_;
};

// Trapezoidal collocation of the states and costates on interval [k, k+1]:
//   x~_{k+1} - x~_k - h/2 (F_k + F_{k+1}) = 0,  lambda~_{k+1} - lambda~_k + h/2 (G_k + G_{k+1}) = 0.
class IntervalResidual : public ceres::SizedCostFunction<kW, kW, kW> {
 public:
  IntervalResidual(const Transcription* tr, int k) : tr_(tr), k_(k) {}
  bool Evaluate(const double* const* p, double* r, double** J) const final {
    const NodeData& a = tr_->nodes[k_];
    const NodeData& b = tr_->nodes[k_ + 1];
    if (!a.valid || !b.valid) return false;
    const double h = tr_->s[k_ + 1] - tr_->s[k_];
    for (int i = 0; i < kNumStates; ++i) {
      r[i] = p[1][i] - p[0][i] - 0.5 * h * (a.F(i) + b.F(i));
      r[kNumStates + i] =
          p[1][kNumStates + i] - p[0][kNumStates + i] + 0.5 * h * (a.G(i) + b.G(i));
    }
    if (J == nullptr) return true;
    for (int side = 0; side < 2; ++side) {
      if (J[side] == nullptr) continue;
      const NodeData& d = side == 0 ? a : b;
      const double sign = side == 0 ? -1.0 : 1.0;
      Eigen::Map<Eigen::Matrix<double, kW, kW, Eigen::RowMajor>> M(J[side]);
      M.topLeftCorner<kNumStates, kNumStates>() = -0.5 * h * d.dF_dx;
      M.topRightCorner<kNumStates, kNumStates>() = -0.5 * h * d.dF_dl;
      M.bottomLeftCorner<kNumStates, kNumStates>() = 0.5 * h * d.dG_dx;
      M.bottomRightCorner<kNumStates, kNumStates>() = 0.5 * h * d.dG_dl;
      M.diagonal().array() += sign;
    }
    return true;
  }

 private:
  const Transcription* tr_;
  int k_;
};

// Stops Ceres once the residual norm is below the tolerance.
class StopAtTolerance : public ceres::IterationCallback {
 public:
  explicit StopAtTolerance(double tol) : tol_(tol) {}
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
      for (NodeData& d : tr_->nodes) d.u_start = d.u;
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Transcription* tr_;
};

// The barrier weight eps with its relaxation delta = min(1e-3, 0.1 eps) (lap-solver notes).
BarrierWeight WeightFor(double eps) { return {eps, std::min(1e-3, 0.1 * eps)}; }

// Largest |residual| of the system at the current unknowns (state part and all).
void ResidualLevels(Transcription* tr, double* max_all, double* max_state) {
  tr->EvaluateNodes(false);
  *max_all = *max_state = tr->all_valid ? 0.0 : HUGE_VAL;
  if (!tr->all_valid) return;
  for (int k = 0; k + 1 < tr->NumNodes(); ++k) {
    IntervalResidual res(tr, k);
    double r[kW];
    const double* p[2] = {tr->W(k), tr->W(k + 1)};
    res.Evaluate(p, r, nullptr);
    for (int i = 0; i < kW; ++i) {
      *max_all = std::max(*max_all, std::abs(r[i]));
      if (i < kNumStates) *max_state = std::max(*max_state, std::abs(r[i]));
    }
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
  const int n = static_cast<int>(mesh.size());
  Transcription tr;
  tr.v = &v;
  tr.sc = DefaultScales(v);
  tr.s = mesh;
  tr.threads = options.num_threads;
  tr.road.resize(n);
  tr.nodes.resize(n);
  tr.w.assign(static_cast<size_t>(n) * kW, 0.0);
  for (int k = 0; k < n; ++k) {
    tr.road[k] = road.At(mesh[k]);
    for (int i = 0; i < kNumStates; ++i) {
      tr.W(k)[i] = x_guess[k][i] / tr.sc.state[i];
      tr.W(k)[kNumStates + i] = lambda_guess.empty() ? 0.0 : lambda_guess[k][i];
    }
    for (int i = 0; i < kNumControls; ++i)
      tr.nodes[k].u_start[i] = u_guess[k][i] / tr.sc.control[i];
  }

  ceres::Problem::Options popts;
  NodeCallback callback(&tr);
  popts.evaluation_callback = &callback;
  ceres::Problem problem(popts);
  for (int k = 0; k + 1 < n; ++k)
    problem.AddResidualBlock(new IntervalResidual(&tr, k), nullptr, tr.W(k), tr.W(k + 1));
  std::vector<int> first_states(kNumStates), last_costates(kNumStates);
  for (int i = 0; i < kNumStates; ++i) {
    first_states[i] = i;
    last_costates[i] = kNumStates + i;
  }
  problem.SetManifold(tr.W(0), new ceres::SubsetManifold(kW, first_states));  // x(0) fixed
  for (int i = kNumStates; i < kW; ++i) tr.W(n - 1)[i] = 0.0;                 // lambda(s_f) = 0
  problem.SetManifold(tr.W(n - 1), new ceres::SubsetManifold(kW, last_costates));

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
  AcceptControls accept(&tr);
  StopAtTolerance stop(options.residual_tolerance);
  so.callbacks.push_back(&accept);
  so.callbacks.push_back(&stop);

  summary->steps.clear();
  summary->iterations = 0;
  double eps = options.eps_start, factor = options.eps_factor;
  std::vector<double> w_good = tr.w;
  std::vector<NodeData> nodes_good = tr.nodes;
  bool first = true, failed = false;
  int retries = 0;
  std::vector<ContinuationStep> good;
  double good_max_all = HUGE_VAL, good_max_state = HUGE_VAL;  // residual levels of w_good
  while (true) {
    tr.weight = WeightFor(eps);
    so.use_nonmonotonic_steps = first;
    so.initial_trust_region_radius = first ? 1e4 : 1e12;
    ceres::Solver::Summary cs;
    const auto t0 = std::chrono::steady_clock::now();
    ceres::Solve(so, &problem, &cs);
    double max_all, max_state;
    ResidualLevels(&tr, &max_all, &max_state);
    ContinuationStep step;
    step.eps = eps;
    step.iterations = static_cast<int>(cs.iterations.size());
    step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    step.converged = tr.all_valid && max_all <= 10.0 * options.residual_tolerance;
    step.lap_time = tr.all_valid ? tr.LapTime() : 0.0;
    summary->iterations += step.iterations;
    summary->steps.push_back(step);
    {
      std::ostringstream o;
      o << "eps " << eps << ": " << (step.converged ? "converged" : "FAILED") << " in "
        << step.iterations << " iterations, " << step.seconds << " s, lap " << step.lap_time
        << " s, max residual " << max_all;
      Log(LogKind::kInfo, o.str());
    }
    if (step.converged) {
      good.push_back(step);
      good_max_all = max_all;
      good_max_state = max_state;
      w_good = tr.w;
      nodes_good = tr.nodes;
      first = false;
      retries = 0;
      for (NodeData& d : tr.nodes) d.u_start = d.u;
      if (eps <= options.eps_end * (1 + 1e-12)) break;
      eps = std::max(options.eps_end, eps * factor);
    } else {
      if (first || ++retries > options.max_retries) {
        failed = true;
        break;
      }
      tr.w = w_good;
      tr.nodes = nodes_good;
      const double last = good.back().eps;
      factor = std::sqrt(eps / last);
      eps = last * factor;
    }
  }
  if (!good.empty()) {  // else keep the last iterate of the failed first solve: it shows where
    tr.w = w_good;      // the solve got stuck
    tr.nodes = nodes_good;
  }

  LapSolution sol;
  sol.s = mesh;
  sol.x.resize(n);
  sol.lambda.resize(n);
  sol.u.resize(n);
  sol.t.assign(n, 0.0);
  summary->max_violation.assign(kNumConstraints, -HUGE_VAL);
  summary->control_failures = 0;
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < kNumStates; ++i) {
      sol.x[k][i] = tr.W(k)[i] * tr.sc.state[i];
      sol.lambda[k][i] = tr.W(k)[kNumStates + i];
    }
    for (int i = 0; i < kNumControls; ++i) sol.u[k][i] = tr.nodes[k].u[i] * tr.sc.control[i];
    if (k > 0)
      sol.t[k] = sol.t[k - 1] + 0.5 * (mesh[k] - mesh[k - 1]) *
                                     (tr.nodes[k - 1].dt_ds + tr.nodes[k].dt_ds);
    if (!tr.nodes[k].control_converged) ++summary->control_failures;
    const ModelPoint<double> m = EvaluateModel(v, sol.x[k], sol.u[k], tr.road[k]);
    const ConstraintVector<double> g = EvaluateConstraints(v, sol.x[k], sol.u[k], tr.road[k], m);
    for (int j = 0; j < kNumConstraints; ++j)
      summary->max_violation[j] = std::max(summary->max_violation[j], g[j]);
  }
  sol.eps = good.empty() ? eps : good.back().eps;
  sol.lap_time = sol.t.back();
  sol.lap_time_extrapolated = sol.lap_time;
  if (good.size() >= 2) {
    const ContinuationStep& a = good[good.size() - 2];
    const ContinuationStep& b = good.back();
    sol.lap_time_extrapolated = b.lap_time - (a.lap_time - b.lap_time) * b.eps / (a.eps - b.eps);
  }
  summary->max_residual = good_max_all;
  summary->max_state_defect = good_max_state;
  const double worst = *std::max_element(summary->max_violation.begin(),
                                         summary->max_violation.end());
  std::ostringstream why;
  if (failed) why << "continuation failed at eps " << eps << "; ";
  if (!(good_max_all <= 10.0 * options.residual_tolerance))
    why << "residual " << good_max_all << "; ";
  if (!(worst <= options.constraint_tolerance)) why << "constraint violated by " << worst << "; ";
  if (summary->control_failures > 0)
    why << summary->control_failures << " nodes without converged controls; ";
  summary->message = why.str();
  summary->converged = summary->message.empty();
  summary->solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sol;
}

}  // namespace ttz::lap
