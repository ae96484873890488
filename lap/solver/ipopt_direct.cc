#include "lap/solver/ipopt_direct.h"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>
#include <utility>

#include "lap/solver/direct_node.h"
#include "lap/solver/hamiltonian.h"

namespace ttz::lap {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr int kLowerTriangle = kNodeVars * (kNodeVars + 1) / 2;  // Hessian entries per node
constexpr double kMaxStateDefect = 1e-6;   // scaled trapezoidal defect of an accepted answer
constexpr double kMaxViolation = 1e-4;     // largest g_j > 0 (relative) of an accepted answer

// Position of entry (a, b), a >= b, in a node's lower triangle, row by row.
constexpr int TriangleEntry(int a, int b) { return a * (a + 1) / 2 + b; }

// Runs ok(k) for every node k in [0, n), the nodes split in `threads` contiguous parts; true if
// every call returned true.
template <typename F>
bool ForEachNode(int n, int threads, F ok) {
  const int parts = std::max(1, threads);
  std::vector<char> part_ok(parts, 1);
  auto work = [&](int p) {
    for (int k = n * p / parts; k < n * (p + 1) / parts && part_ok[p]; ++k) part_ok[p] = ok(k);
  };
  std::vector<std::thread> pool;
  for (int p = 1; p < parts; ++p) pool.emplace_back(work, p);
  work(0);
  for (std::thread& t : pool) t.join();
  return std::all_of(part_ok.begin(), part_ok.end(), [](char c) { return c != 0; });
}

// The transcription's data: mesh, nodes and the control-rate weight (ipopt_direct.h).
struct Transcription {
  std::vector<double> s, h;  // nodes and interval lengths h_k = s_{k+1} - s_k [m]
  std::vector<DirectNode> nodes;
  Scales sc;
  double rate_weight = 0.0;  // c [s m]
  int threads = 1;           // for the node evaluations

  int NumNodes() const { return static_cast<int>(s.size()); }
  int NumIntervals() const { return NumNodes() - 1; }
  int NumVars() const { return kNodeVars * NumNodes(); }
  int Var(int k, int c) const { return kNodeVars * k + c; }
  int DefectRow(int k, int i) const { return kNumStates * k + i; }
  int PathRow(int k, int j) const { return kNumStates * NumIntervals() + kNumConstraints * k + j; }
  int NumRows() const { return PathRow(NumNodes(), 0); }
  // Trapezoidal quadrature weight of node k: (h_{k-1} + h_k) / 2 [m].
  double Weight(int k) const {
    return 0.5 * ((k > 0 ? h[k - 1] : 0.0) + (k < NumIntervals() ? h[k] : 0.0));
  }
};

// The node values (and Jacobians) of the current Ipopt point, evaluated once per point.
class NodeCache {
 public:
  explicit NodeCache(const Transcription* tr)
      : tr_(tr), z_(tr->NumNodes()), y_(tr->NumNodes()), J_(tr->NumNodes()) {}

  // Makes y (and J when `derivatives`) current at x; false where the model is undefined.
  bool Update(const Number* x, bool new_x, bool derivatives) {
    if (new_x || !have_point_) {
      for (int k = 0; k < tr_->NumNodes(); ++k)
        z_[k] = Eigen::Map<const NodePoint>(x + tr_->Var(k, 0));
      have_point_ = true;
      have_values_ = have_jacobians_ = false;
    }
    if (derivatives && !have_jacobians_) {
      ok_ = ForEachNode(tr_->NumNodes(), tr_->threads, [&](int k) {
        return NodeDerivatives(tr_->nodes[k], z_[k], &y_[k], &J_[k]);
      });
      have_values_ = have_jacobians_ = true;
    } else if (!have_values_) {
      ok_ = ForEachNode(tr_->NumNodes(), tr_->threads,
                        [&](int k) { return NodeValues(tr_->nodes[k], z_[k], &y_[k]); });
      have_values_ = true;
    }
    return ok_;
  }
  const NodePoint& z(int k) const { return z_[k]; }
  const NodeOutputs& y(int k) const { return y_[k]; }
  const NodeJacobian& J(int k) const { return J_[k]; }

 private:
  const Transcription* tr_;
  std::vector<NodePoint> z_;
  std::vector<NodeOutputs> y_;
  std::vector<NodeJacobian> J_;
  bool have_point_ = false, have_values_ = false, have_jacobians_ = false, ok_ = false;
};

// Lap time sum_k w_k / sdot_k (trapezoidal rule, eq. 38) of the cached values [s].
double LapTime(const Transcription& tr, const NodeCache& cache) {
  double t = 0.0;
  for (int k = 0; k < tr.NumNodes(); ++k) t += tr.Weight(k) * cache.y(k)(kOutTime);
  return t;
}

// The nonlinear program of ipopt_direct.h for Ipopt.
class LapNlp : public Ipopt::TNLP {
 public:
  LapNlp(const Transcription* tr, std::vector<double> start)
      : tr_(tr), cache_(tr), start_(std::move(start)) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) final {
    n = tr_->NumVars();
    m = tr_->NumRows();
    nnz_jac_g = tr_->NumIntervals() * kNumStates * 2 * kNodeVars +
                tr_->NumNodes() * kNumConstraints * kNodeVars;
    nnz_h_lag = tr_->NumNodes() * kLowerTriangle + NumRateCouplings();
    index_style = C_STYLE;
    return true;
  }

  // x~_0 fixed by equal bounds (Ipopt makes it a parameter); g_j <= 0; defects = 0.
  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) final {
    std::fill(x_l, x_l + n, -2e19);  // Ipopt's "no bound" (nlp_lower_bound_inf = -1e19)
    std::fill(x_u, x_u + n, 2e19);
    for (int i = 0; i < kNumStates; ++i) x_l[i] = x_u[i] = start_[i];
    std::fill(g_l, g_l + m, 0.0);
    std::fill(g_u, g_u + m, 0.0);
    std::fill(g_l + tr_->PathRow(0, 0), g_l + m, -2e19);
    return true;
  }

  bool get_starting_point(Index, bool init_x, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) final {
    if (init_x) std::copy(start_.begin(), start_.end(), x);
    return true;
  }

  bool eval_f(Index, const Number* x, bool new_x, Number& obj_value) final {
    if (!cache_.Update(x, new_x, false)) return false;
    obj_value = LapTime(*tr_, cache_) + RateTerm(x);
    return true;
  }

  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad_f) final {
    if (!cache_.Update(x, new_x, true)) return false;
    std::fill(grad_f, grad_f + n, 0.0);
    for (int k = 0; k < tr_->NumNodes(); ++k)
      for (int c = 0; c < kNodeVars; ++c)
        grad_f[tr_->Var(k, c)] += tr_->Weight(k) * cache_.J(k)(kOutTime, c);
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const int a = tr_->Var(k, kNumStates + i), b = tr_->Var(k + 1, kNumStates + i);
        const double d = 2.0 * tr_->rate_weight * (x[b] - x[a]) / tr_->h[k];
        grad_f[a] -= d;
        grad_f[b] += d;
      }
    return true;
  }

  bool eval_g(Index, const Number* x, bool new_x, Index, Number* g) final {
    if (!cache_.Update(x, new_x, false)) return false;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumStates; ++i)
        g[tr_->DefectRow(k, i)] = x[tr_->Var(k + 1, i)] - x[tr_->Var(k, i)] -
                                  0.5 * tr_->h[k] * (cache_.y(k)(i) + cache_.y(k + 1)(i));
    for (int k = 0; k < tr_->NumNodes(); ++k)
      for (int j = 0; j < kNumConstraints; ++j) g[tr_->PathRow(k, j)] = cache_.y(k)(kOutG + j);
    return true;
  }

  // Dense blocks: each defect row over the 2 x 13 unknowns of its interval, each constraint row
  // over the 13 of its node.
  bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index, Index* iRow, Index* jCol,
                  Number* values) final {
    if (values == nullptr) return JacobianStructure(iRow, jCol);
    if (!cache_.Update(x, new_x, true)) return false;
    int e = 0;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumStates; ++i)
        for (int side = 0; side < 2; ++side)
          for (int c = 0; c < kNodeVars; ++c) {
            const double identity = c == i ? (side == 0 ? -1.0 : 1.0) : 0.0;
            values[e++] = identity - 0.5 * tr_->h[k] * cache_.J(k + side)(kOutDxDs + i, c);
          }
    for (int k = 0; k < tr_->NumNodes(); ++k)
      for (int j = 0; j < kNumConstraints; ++j)
        for (int c = 0; c < kNodeVars; ++c) values[e++] = cache_.J(k)(kOutG + j, c);
    return true;
  }

  // Hessian of the Lagrangian sigma f + sum lambda_r c_r: per node the 13 x 13 Hessian of
  // sigma w_k / sdot_k - sum_i (h_{k-1} lambda_{k-1,i} + h_k lambda_{k,i}) / 2 x~'_{k,i}
  // + sum_j mu_{k,j} g_{k,j} (lower triangle), plus the constant control-rate term.
  bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda,
              bool, Index, Index* iRow, Index* jCol, Number* values) final {
    if (values == nullptr) return HessianStructure(iRow, jCol);
    if (!cache_.Update(x, new_x, false)) return false;
    const bool ok = ForEachNode(tr_->NumNodes(), tr_->threads, [&](int k) {
      NodeHessian H;
      if (!NodeWeightedHessian(tr_->nodes[k], cache_.z(k), NodeWeights(k, obj_factor, lambda), &H))
        return false;
      Number* block = values + k * kLowerTriangle;
      for (int a = 0; a < kNodeVars; ++a)
        for (int b = 0; b <= a; ++b) block[TriangleEntry(a, b)] = H(a, b);
      return true;
    });
    if (!ok) return false;
    AddRateHessian(obj_factor, values);
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index m, const Number*, const Number* lambda, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) final {
    x_final_.assign(x, x + n);
    lambda_final_.assign(lambda, lambda + m);
  }

  const std::vector<double>& x_final() const { return x_final_; }
  const std::vector<double>& lambda_final() const { return lambda_final_; }

 private:
  int NumRateCouplings() const {
    return tr_->rate_weight > 0.0 ? tr_->NumIntervals() * kNumControls : 0;
  }

  // c sum_k sum_i (u~_{k+1,i} - u~_{k,i})^2 / h_k [s].
  double RateTerm(const Number* x) const {
    double r = 0.0;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const double d = x[tr_->Var(k + 1, kNumStates + i)] - x[tr_->Var(k, kNumStates + i)];
        r += tr_->rate_weight * d * d / tr_->h[k];
      }
    return r;
  }

  NodeOutputs NodeWeights(int k, double obj_factor, const Number* lambda) const {
    NodeOutputs w = NodeOutputs::Zero();
    w(kOutTime) = obj_factor * tr_->Weight(k);
    for (int i = 0; i < kNumStates; ++i) {
      if (k > 0) w(kOutDxDs + i) -= 0.5 * tr_->h[k - 1] * lambda[tr_->DefectRow(k - 1, i)];
      if (k < tr_->NumIntervals())
        w(kOutDxDs + i) -= 0.5 * tr_->h[k] * lambda[tr_->DefectRow(k, i)];
    }
    for (int j = 0; j < kNumConstraints; ++j) w(kOutG + j) = lambda[tr_->PathRow(k, j)];
    return w;
  }

  void AddRateHessian(double obj_factor, Number* values) const {
    if (NumRateCouplings() == 0) return;
    Number* coupling = values + tr_->NumNodes() * kLowerTriangle;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const double d = 2.0 * obj_factor * tr_->rate_weight / tr_->h[k];
        const int c = kNumStates + i;
        values[k * kLowerTriangle + TriangleEntry(c, c)] += d;
        values[(k + 1) * kLowerTriangle + TriangleEntry(c, c)] += d;
        *coupling++ = -d;
      }
  }

  bool JacobianStructure(Index* iRow, Index* jCol) const {
    int e = 0;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumStates; ++i)
        for (int side = 0; side < 2; ++side)
          for (int c = 0; c < kNodeVars; ++c, ++e) {
            iRow[e] = tr_->DefectRow(k, i);
            jCol[e] = tr_->Var(k + side, c);
          }
    for (int k = 0; k < tr_->NumNodes(); ++k)
      for (int j = 0; j < kNumConstraints; ++j)
        for (int c = 0; c < kNodeVars; ++c, ++e) {
          iRow[e] = tr_->PathRow(k, j);
          jCol[e] = tr_->Var(k, c);
        }
    return true;
  }

  bool HessianStructure(Index* iRow, Index* jCol) const {
    int e = 0;
    for (int k = 0; k < tr_->NumNodes(); ++k)
      for (int a = 0; a < kNodeVars; ++a)
        for (int b = 0; b <= a; ++b, ++e) {
          iRow[e] = tr_->Var(k, a);
          jCol[e] = tr_->Var(k, b);
        }
    if (NumRateCouplings() == 0) return true;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int i = 0; i < kNumControls; ++i, ++e) {
        iRow[e] = tr_->Var(k + 1, kNumStates + i);
        jCol[e] = tr_->Var(k, kNumStates + i);
      }
    return true;
  }

  const Transcription* tr_;
  NodeCache cache_;
  std::vector<double> start_;
  std::vector<double> x_final_, lambda_final_;
};

Transcription MakeTranscription(const Vehicle& v, const RoadTrack& road,
                                const std::vector<double>& mesh, const IpoptOptions& options) {
  Transcription tr;
  tr.s = mesh;
  tr.sc = DefaultScales(v);
  tr.rate_weight = options.control_rate_weight;
  tr.threads = options.num_threads;
  for (int k = 0; k + 1 < tr.NumNodes(); ++k) tr.h.push_back(mesh[k + 1] - mesh[k]);
  for (double s : mesh) tr.nodes.push_back({&v, tr.sc, road.At(s)});
  return tr;
}

// The guess as Ipopt's unknowns z_k = (x_k / S, u_k / S_u).
std::vector<double> ScaledGuess(const Transcription& tr,
                                const std::vector<StateVector<double>>& x_guess,
                                const std::vector<ControlVector<double>>& u_guess) {
  std::vector<double> z(tr.NumVars());
  for (int k = 0; k < tr.NumNodes(); ++k) {
    for (int i = 0; i < kNumStates; ++i) z[tr.Var(k, i)] = x_guess[k][i] / tr.sc.state[i];
    for (int i = 0; i < kNumControls; ++i)
      z[tr.Var(k, kNumStates + i)] = u_guess[k][i] / tr.sc.control[i];
  }
  return z;
}

Ipopt::SmartPtr<Ipopt::IpoptApplication> MakeApplication(const IpoptOptions& o) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", o.print_level);
  if (o.print_level == 0) app->Options()->SetStringValue("sb", "yes");  // no banner
  app->Options()->SetStringValue("hessian_approximation", "exact");
  app->Options()->SetStringValue("mu_strategy", o.mu_strategy);
  app->Options()->SetStringValue("linear_solver", "mumps");
  app->Options()->SetNumericValue("tol", o.tolerance);
  app->Options()->SetIntegerValue("max_iter", o.max_iterations);
  return app;
}

std::string StatusName(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
    default: return "Ipopt status " + std::to_string(static_cast<int>(status));
  }
}

// The costates of the scaled states, p = -(Ipopt's defect multipliers): with the Lagrangian
// t + sum_k lambda_k^T c_k, stationarity in x~_k is the trapezoidal form of p' = -H_x~ (eq. 38)
// for p = -lambda. The multipliers belong to the intervals (their midpoints): an interior node
// takes the mean of its two, an end node the linear extrapolation of the two nearest.
std::vector<StateVector<double>> CostatesFromMultipliers(const Transcription& tr,
                                                         const std::vector<double>& lambda) {
  const int n = tr.NumNodes(), last = tr.NumIntervals() - 1;
  auto at = [&](int k, int i) { return -lambda[tr.DefectRow(k, i)]; };
  std::vector<StateVector<double>> p(n);
  for (int i = 0; i < kNumStates; ++i) {
    for (int k = 1; k + 1 < n; ++k) p[k][i] = 0.5 * (at(k - 1, i) + at(k, i));
    if (last == 0) {
      p[0][i] = p[1][i] = at(0, i);
      continue;
    }
    p[0][i] = at(0, i) + (at(0, i) - at(1, i)) * tr.h[0] / (tr.h[0] + tr.h[1]);
    p[n - 1][i] =
        at(last, i) + (at(last, i) - at(last - 1, i)) * tr.h[last] / (tr.h[last] + tr.h[last - 1]);
  }
  return p;
}

// Fills the solution and the checks of the answer (state defects, constraint violations) from
// the node values at the final point.
void CheckAnswer(const Transcription& tr, const NodeCache& cache, LapSolution* sol,
                 SolveSummary* summary) {
  const int n = tr.NumNodes();
  sol->x.resize(n);
  sol->u.resize(n);
  sol->t.assign(n, 0.0);
  summary->max_violation.assign(kNumConstraints, -HUGE_VAL);
  summary->max_state_defect = 0.0;
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < kNumStates; ++i) sol->x[k][i] = cache.z(k)(i) * tr.sc.state[i];
    for (int i = 0; i < kNumControls; ++i)
      sol->u[k][i] = cache.z(k)(kNumStates + i) * tr.sc.control[i];
    for (int j = 0; j < kNumConstraints; ++j)
      summary->max_violation[j] = std::max(summary->max_violation[j], cache.y(k)(kOutG + j));
    if (k == 0) continue;
    sol->t[k] =
        sol->t[k - 1] + 0.5 * tr.h[k - 1] * (cache.y(k - 1)(kOutTime) + cache.y(k)(kOutTime));
    for (int i = 0; i < kNumStates; ++i) {
      const double defect = cache.z(k)(i) - cache.z(k - 1)(i) -
                            0.5 * tr.h[k - 1] * (cache.y(k - 1)(i) + cache.y(k)(i));
      summary->max_state_defect = std::max(summary->max_state_defect, std::abs(defect));
    }
  }
  sol->lap_time = sol->lap_time_extrapolated = sol->t.back();
}

}  // namespace

LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh,
                             const std::vector<StateVector<double>>& x_guess,
                             const std::vector<ControlVector<double>>& u_guess,
                             const IpoptOptions& options, SolveSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  const Transcription tr = MakeTranscription(v, road, mesh, options);
  LapNlp* nlp = new LapNlp(&tr, ScaledGuess(tr, x_guess, u_guess));
  const Ipopt::SmartPtr<Ipopt::TNLP> owner = nlp;  // Ipopt's reference counting frees it
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = MakeApplication(options);
  std::ostringstream why;
  Ipopt::ApplicationReturnStatus status = app->Initialize();
  if (status == Ipopt::Solve_Succeeded) status = app->OptimizeTNLP(owner);
  if (status != Ipopt::Solve_Succeeded) why << "Ipopt: " << StatusName(status) << "; ";

  LapSolution sol;
  sol.s = mesh;
  *summary = SolveSummary{};
  const Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
  if (Ipopt::IsValid(stats)) {
    summary->iterations = stats->IterationCount();
    double dual, primal, complementarity;
    stats->ScaledInfeasibilities(dual, primal, complementarity, summary->max_residual);
  }
  NodeCache cache(&tr);
  if (nlp->x_final().empty() || !cache.Update(nlp->x_final().data(), true, false)) {
    why << "no answer to check (model undefined at Ipopt's last point); ";
  } else {
    CheckAnswer(tr, cache, &sol, summary);
    sol.lambda = CostatesFromMultipliers(tr, nlp->lambda_final());
    if (!(summary->max_state_defect <= kMaxStateDefect))
      why << "state defect " << summary->max_state_defect << "; ";
    for (int j = 0; j < kNumConstraints; ++j)
      if (!(summary->max_violation[j] <= kMaxViolation))
        why << kConstraintNames[j] << " violated by " << summary->max_violation[j] << "; ";
  }
  summary->message = why.str();
  summary->converged = summary->message.empty();
  summary->solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sol;
}

}  // namespace ttz::lap
