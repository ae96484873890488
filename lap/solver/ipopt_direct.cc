#include "lap/solver/ipopt_direct.h"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/parse_number.h"
#include "lap/solver/direct_node.h"
#include "lap/solver/hamiltonian.h"
#include "lap/solver/parallel.h"

namespace ttz::lap {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Unknowns of one interval k, contiguous in Ipopt's vector: x~_k, u~_k, x~_{k+1}.
constexpr int kIntervalVars = 2 * kNumStates + kNumControls;
constexpr int kLowerTriangle = kIntervalVars * (kIntervalVars + 1) / 2;  // Hessian entries
constexpr int kStateTriangle = kNumStates * (kNumStates + 1) / 2;       // ... of a node
constexpr double kMaxStateDefect = 1e-6;   // scaled midpoint defect of an accepted answer
constexpr double kMaxViolation = 1e-4;     // largest g_j > 0 (relative) of an accepted answer

// Position of entry (a, b), a >= b, in an interval's lower triangle, row by row.
constexpr int TriangleEntry(int a, int b) { return a * (a + 1) / 2 + b; }

// The midpoint variable z_mid = ((x~_k + x~_{k+1}) / 2, u~_k) that the interval's unknown a
// (0 <= a < kIntervalVars) enters, and dz_mid / d(unknown a): 1/2 for the states, 1 for the
// controls.
constexpr int MidVar(int a) {
  return a < kNodeVars ? a : a - kNodeVars;
}
constexpr double MidFactor(int a) { return a < kNumStates || a >= kNodeVars ? 0.5 : 1.0; }
// Whether constraint j at a midpoint depends on interval unknown a (constraints.h: the states
// alone, and not all of them): the Jacobian's structure leaves the others out.
constexpr bool MidConstraintUses(int j, int a) {
  return MidVar(a) < kNumStates && ConstraintUsesState(j, MidVar(a));
}
// The constraints that are rows at the nodes (with node constraints): those that do not bound
// one state; the state bounds are bounds of the nodes' unknowns (Transcription).
constexpr int kNumNodeRows = [] {
  int n = 0;
  for (int j = 0; j < kNumConstraints; ++j) n += IsStateBound(j) ? 0 : 1;
  return n;
}();
constexpr std::array<int, kNumNodeRows> kNodeRowKinds = [] {
  std::array<int, kNumNodeRows> kinds{};
  int n = 0;
  for (int j = 0; j < kNumConstraints; ++j)
    if (!IsStateBound(j)) kinds[n++] = j;
  return kinds;
}();
// Structural non-zeros of the node rows at one node.
constexpr int NodeRowEntries() {
  int n = 0;
  for (int j : kNodeRowKinds) n += ConstraintStateCount(j);
  return n;
}
constexpr double kNoBound = 2e19;  // beyond Ipopt's "no bound" (nlp_upper_bound_inf = 1e19)

// The transcription's data: mesh, midpoints (ipopt_direct.h).
struct Transcription {
  std::vector<double> s, h;  // nodes and interval lengths h_k = s_{k+1} - s_k [m]
  std::vector<DirectNode> mids;   // the model's data at the interval midpoints s_{k+1/2}
  std::vector<DirectNode> nodes;  // ... at the nodes s_k (for the node constraints)
  Scales sc;
  double rate_weight = 0.0;       // c [s m] of the control-rate term (ipopt_direct.h)
  bool node_constraints = true;   // g_j at the nodes 1..N too (ipopt_direct.h)
  int threads = 1;                // for the midpoint evaluations
  // Where the path constraints go. With node constraints, a constraint that bounds one state
  // (IsStateBound) is a bound of that state's unknown at the nodes 1..N (lower, upper), and its
  // row at a midpoint is left out where those bounds imply it: the constraint is affine in the
  // state, whose midpoint value is the mean of the nodes' (the start state's at node 0). The
  // feasible set is the same, with fewer rows for Ipopt's KKT matrix: 12 inequality rows per
  // interval on a road of constant width instead of 26. The other constraints, and every one
  // without node constraints, are rows at the midpoints (and nodes).
  std::vector<int> mid_first;  // interval k's rows are PathRow(mid_first[k] .. mid_first[k + 1] - 1)
  std::vector<int> mid_kind;   // the constraint of each midpoint row
  std::vector<double> lower, upper;  // bounds of the unknowns (scaled; the start's set by LapNlp)

  int NumNodes() const { return static_cast<int>(s.size()); }
  int NumIntervals() const { return NumNodes() - 1; }
  // Ipopt's unknowns: x~_0, u~_0, x~_1, u~_1, ..., u~_{N-1}, x~_N.
  int NumVars() const { return kNodeVars * NumIntervals() + kNumStates; }
  int State(int k, int i) const { return kNodeVars * k + i; }
  int Control(int k, int i) const { return kNodeVars * k + kNumStates + i; }
  int IntervalVar(int k, int a) const { return kNodeVars * k + a; }  // a < kIntervalVars
  int DefectRow(int k, int i) const { return kNumStates * k + i; }
  int PathRow(int r) const { return kNumStates * NumIntervals() + r; }  // midpoint row r
  int NumMidRows() const { return mid_first.back(); }
  // Row of node row kind n (kNodeRowKinds) at node k, 1 <= k <= N (node 0 is the fixed start).
  int NodeRow(int k, int n) const { return PathRow(NumMidRows()) + kNumNodeRows * (k - 1) + n; }
  int NumNodeRows() const { return node_constraints ? kNumNodeRows * NumIntervals() : 0; }
  int NumRows() const { return PathRow(NumMidRows()) + NumNodeRows(); }
  // Distance between the midpoints of intervals k - 1 and k (0 < k < N) [m].
  double MidSpacing(int k) const { return 0.5 * (h[k - 1] + h[k]); }
};

// The midpoint values (and Jacobians) of the current Ipopt point, evaluated once per point.
class MidCache {
 public:
  explicit MidCache(const Transcription* tr)
      : tr_(tr), z_(tr->NumIntervals()), y_(tr->NumIntervals()), J_(tr->NumIntervals()),
        x_(tr->NumNodes()), g_(tr->NumNodes()), Jg_(tr->NumNodes()) {}

  // Makes y (and J when `derivatives`) current at x; false where the model is undefined.
  bool Update(const Number* x, bool new_x, bool derivatives) {
    if (new_x || !have_point_) {
      for (int k = 0; k < tr_->NumIntervals(); ++k)
        for (int a = 0; a < kNodeVars; ++a)
          z_[k](a) = a < kNumStates
                         ? 0.5 * (x[tr_->State(k, a)] + x[tr_->State(k + 1, a)])
                         : x[tr_->Control(k, a - kNumStates)];
      for (int k = 0; k < tr_->NumNodes(); ++k)
        for (int i = 0; i < kNumStates; ++i) x_[k](i) = x[tr_->State(k, i)];
      have_point_ = true;
      have_values_ = have_jacobians_ = false;
    }
    if (derivatives && !have_jacobians_) {
      ok_ = ForEachInterval(tr_->NumIntervals(), tr_->threads, [&](int k) {
        return NodeDerivatives(tr_->mids[k], z_[k], &y_[k], &J_[k]) && UpdateNode(k + 1);
      });
      have_values_ = have_jacobians_ = true;
    } else if (!have_values_) {
      ok_ = ForEachInterval(tr_->NumIntervals(), tr_->threads, [&](int k) {
        return NodeValues(tr_->mids[k], z_[k], &y_[k]) && UpdateNode(k + 1);
      });
      have_values_ = true;
    }
    return ok_;
  }
  const NodePoint& z(int k) const { return z_[k]; }
  const NodeOutputs& y(int k) const { return y_[k]; }
  const NodeJacobian& J(int k) const { return J_[k]; }
  // Node k's scaled state, constraints and their Jacobian (1 <= k <= N, with node constraints).
  const StatePoint& x(int k) const { return x_[k]; }
  const NodeConstraintValues& g(int k) const { return g_[k]; }
  const NodeConstraintJacobian& Jg(int k) const { return Jg_[k]; }

 private:
  // The node constraints and their Jacobian (always both: the tyre and power train alone are cheap).
  bool UpdateNode(int k) {
    return !tr_->node_constraints || NodeConstraints(tr_->nodes[k], x_[k], &g_[k], &Jg_[k]);
  }

  const Transcription* tr_;
  std::vector<NodePoint> z_;
  std::vector<NodeOutputs> y_;
  std::vector<NodeJacobian> J_;
  std::vector<StatePoint> x_;
  std::vector<NodeConstraintValues> g_;
  std::vector<NodeConstraintJacobian> Jg_;
  bool have_point_ = false, have_values_ = false, have_jacobians_ = false, ok_ = false;
};

// Lap time sum_k h_k / sdot_{k+1/2} (midpoint rule, eq. 38) of the cached values [s].
double LapTime(const Transcription& tr, const MidCache& cache) {
  double t = 0.0;
  for (int k = 0; k < tr.NumIntervals(); ++k) t += tr.h[k] * cache.y(k)(kOutTime);
  return t;
}

// Effort sum_k h_k (lap/model/cost.h) at the interval midpoints of the cached values [s].
double Effort(const Transcription& tr, const MidCache& cache) {
  double e = 0.0;
  for (int k = 0; k < tr.NumIntervals(); ++k) e += tr.h[k] * cache.y(k)(kOutEffort);
  return e;
}

// The weights of interval k's outputs in the Lagrangian sigma f + sum lambda_r c_r, less the
// defects' linear terms: sigma h_k on 1 / sdot and on the effort, -h_k lambda_{k,i} on x~'_i,
// mu_{k,j} on g_j.
NodeOutputs IntervalWeights(const Transcription& tr, int k, double obj_factor,
                            const Number* lambda) {
  NodeOutputs w;
  w(kOutTime) = obj_factor * tr.h[k];
  w(kOutEffort) = obj_factor * tr.h[k];
  for (int i = 0; i < kNumStates; ++i) w(kOutDxDs + i) = -tr.h[k] * lambda[tr.DefectRow(k, i)];
  for (int j = 0; j < kNumConstraints; ++j) w(kOutG + j) = 0.0;
  for (int r = tr.mid_first[k]; r < tr.mid_first[k + 1]; ++r)
    w(kOutG + tr.mid_kind[r]) = lambda[tr.PathRow(r)];
  return w;
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
    nnz_jac_g = tr_->NumIntervals() * kNumStates * kIntervalVars +
                (tr_->node_constraints ? tr_->NumIntervals() * NodeRowEntries() : 0);
    for (int j : tr_->mid_kind) nnz_jac_g += 2 * ConstraintStateCount(j);
    nnz_h_lag = tr_->NumIntervals() * kLowerTriangle + 3 * NumRatePairs() + NumNodeHessian();
    index_style = C_STYLE;
    return true;
  }

  // x~_0 fixed by equal bounds (Ipopt makes it a parameter); the state bounds; g_j <= 0;
  // defects = 0.
  bool get_bounds_info(Index, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) final {
    std::copy(tr_->lower.begin(), tr_->lower.end(), x_l);
    std::copy(tr_->upper.begin(), tr_->upper.end(), x_u);
    for (int i = 0; i < kNumStates; ++i) x_l[i] = x_u[i] = start_[i];
    std::fill(g_l, g_l + m, 0.0);
    std::fill(g_u, g_u + m, 0.0);
    std::fill(g_l + tr_->PathRow(0), g_l + m, -kNoBound);
    return true;
  }

  bool get_starting_point(Index, bool init_x, Number* x, bool, Number*, Number*, Index, bool,
                          Number*) final {
    if (init_x) std::copy(start_.begin(), start_.end(), x);
    return true;
  }

  bool eval_f(Index, const Number* x, bool new_x, Number& obj_value) final {
    if (!cache_.Update(x, new_x, false)) return false;
    obj_value = LapTime(*tr_, cache_) + Effort(*tr_, cache_) + RateTerm(x);
    return true;
  }

  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad_f) final {
    if (!cache_.Update(x, new_x, true)) return false;
    std::fill(grad_f, grad_f + n, 0.0);
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int a = 0; a < kIntervalVars; ++a)
        grad_f[tr_->IntervalVar(k, a)] +=
            tr_->h[k] * MidFactor(a) *
            (cache_.J(k)(kOutTime, MidVar(a)) + cache_.J(k)(kOutEffort, MidVar(a)));
    if (NumRatePairs() > 0)
      for (int k = 1; k < tr_->NumIntervals(); ++k)
        for (int i = 0; i < kNumControls; ++i) {
          const int a = tr_->Control(k - 1, i), b = tr_->Control(k, i);
          const double d = 2.0 * tr_->rate_weight * (x[b] - x[a]) / tr_->MidSpacing(k);
          grad_f[a] -= d;
          grad_f[b] += d;
        }
    return true;
  }

  bool eval_g(Index, const Number* x, bool new_x, Index, Number* g) final {
    if (!cache_.Update(x, new_x, false)) return false;
    for (int k = 0; k < tr_->NumIntervals(); ++k) {
      for (int i = 0; i < kNumStates; ++i)
        g[tr_->DefectRow(k, i)] = x[tr_->State(k + 1, i)] - x[tr_->State(k, i)] -
                                  tr_->h[k] * cache_.y(k)(kOutDxDs + i);
      for (int r = tr_->mid_first[k]; r < tr_->mid_first[k + 1]; ++r)
        g[tr_->PathRow(r)] = cache_.y(k)(kOutG + tr_->mid_kind[r]);
      for (int n = 0; n < kNumNodeRows && tr_->node_constraints; ++n)
        g[tr_->NodeRow(k + 1, n)] = cache_.g(k + 1)(kNodeRowKinds[n]);
    }
    return true;
  }

  // Each defect row of interval k over its 28 unknowns, each constraint row over the states it
  // depends on (ConstraintUsesState) at the interval's two nodes, or at its node.
  bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index, Index* iRow, Index* jCol,
                  Number* values) final {
    if (values == nullptr) return JacobianStructure(iRow, jCol);
    if (!cache_.Update(x, new_x, true)) return false;
    int e = 0;
    for (int k = 0; k < tr_->NumIntervals(); ++k) {
      const NodeJacobian& J = cache_.J(k);
      for (int i = 0; i < kNumStates; ++i)
        for (int a = 0; a < kIntervalVars; ++a) {
          const double identity = a == i ? -1.0 : (a == kNodeVars + i ? 1.0 : 0.0);
          values[e++] = identity - tr_->h[k] * MidFactor(a) * J(kOutDxDs + i, MidVar(a));
        }
      for (int r = tr_->mid_first[k]; r < tr_->mid_first[k + 1]; ++r)
        for (int a = 0; a < kIntervalVars; ++a)
          if (MidConstraintUses(tr_->mid_kind[r], a))
            values[e++] = MidFactor(a) * J(kOutG + tr_->mid_kind[r], MidVar(a));
    }
    for (int k = 1; k <= tr_->NumIntervals() && tr_->node_constraints; ++k)
      for (int j : kNodeRowKinds)
        for (int i = 0; i < kNumStates; ++i)
          if (ConstraintUsesState(j, i)) values[e++] = cache_.Jg(k)(j, i);
    return true;
  }

  // Hessian of the Lagrangian: per interval, the (states + controls)-square Hessian of w^T y (IntervalWeights) in
  // z_mid by HyperDual numbers (direct_node.cc), mapped to the interval's 24 unknowns by the chain factors 1/2 (states)
  // and 1 (controls). Neighbouring intervals share x~_k: Ipopt adds the duplicate entries.
  bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda,
              bool, Index, Index* iRow, Index* jCol, Number* values) final {
    if (values == nullptr) return HessianStructure(iRow, jCol);
    if (!cache_.Update(x, new_x, false)) return false;
    Number* rate = values + tr_->NumIntervals() * kLowerTriangle;
    for (int k = 1; k < tr_->NumIntervals() && NumRatePairs() > 0; ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const double d = 2.0 * obj_factor * tr_->rate_weight / tr_->MidSpacing(k);
        *rate++ = d;
        *rate++ = d;
        *rate++ = -d;
      }
    Number* node_blocks = rate;
    return ForEachInterval(tr_->NumIntervals(), tr_->threads, [&](int k) {
      NodeHessian H;
      if (!NodeWeightedHessian(tr_->mids[k], cache_.z(k),
                               IntervalWeights(*tr_, k, obj_factor, lambda), &H))
        return false;
      Number* block = values + k * kLowerTriangle;
      for (int a = 0; a < kIntervalVars; ++a)
        for (int b = 0; b <= a; ++b)
          block[TriangleEntry(a, b)] = MidFactor(a) * MidFactor(b) * H(MidVar(a), MidVar(b));
      return !tr_->node_constraints ||
             NodeHessianBlock(k + 1, lambda, node_blocks + k * kStateTriangle);
    });
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
  // Node k's block of the Hessian, the lower triangle of d2(sum_j mu_{k,j} g_j)/dx~_k^2.
  bool NodeHessianBlock(int k, const Number* lambda, Number* block) const {
    NodeConstraintValues w;
    w.setZero();
    for (int n = 0; n < kNumNodeRows; ++n) w(kNodeRowKinds[n]) = lambda[tr_->NodeRow(k, n)];
    StateHessian H;
    if (!NodeConstraintsWeightedHessian(tr_->nodes[k], cache_.x(k), w, &H)) return false;
    for (int a = 0; a < kNumStates; ++a)
      for (int b = 0; b <= a; ++b) block[TriangleEntry(a, b)] = H(a, b);
    return true;
  }

  int NumNodeHessian() const { return tr_->node_constraints ? tr_->NumIntervals() * kStateTriangle : 0; }

  int NumRatePairs() const {
    return tr_->rate_weight > 0.0 ? (tr_->NumIntervals() - 1) * kNumControls : 0;
  }

  // c sum_k sum_i (u~_{k,i} - u~_{k-1,i})^2 / ((h_{k-1} + h_k) / 2) [s].
  double RateTerm(const Number* x) const {
    double r = 0.0;
    for (int k = 1; k < tr_->NumIntervals() && NumRatePairs() > 0; ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const double d = x[tr_->Control(k, i)] - x[tr_->Control(k - 1, i)];
        r += tr_->rate_weight * d * d / tr_->MidSpacing(k);
      }
    return r;
  }

  bool JacobianStructure(Index* iRow, Index* jCol) const {
    int e = 0;
    for (int k = 0; k < tr_->NumIntervals(); ++k) {
      for (int i = 0; i < kNumStates; ++i)
        for (int a = 0; a < kIntervalVars; ++a, ++e) {
          iRow[e] = tr_->DefectRow(k, i);
          jCol[e] = tr_->IntervalVar(k, a);
        }
      for (int r = tr_->mid_first[k]; r < tr_->mid_first[k + 1]; ++r)
        for (int a = 0; a < kIntervalVars; ++a)
          if (MidConstraintUses(tr_->mid_kind[r], a)) {
            iRow[e] = tr_->PathRow(r);
            jCol[e++] = tr_->IntervalVar(k, a);
          }
    }
    for (int k = 1; k <= tr_->NumIntervals() && tr_->node_constraints; ++k)
      for (int n = 0; n < kNumNodeRows; ++n)
        for (int i = 0; i < kNumStates; ++i)
          if (ConstraintUsesState(kNodeRowKinds[n], i)) {
            iRow[e] = tr_->NodeRow(k, n);
            jCol[e++] = tr_->State(k, i);
          }
    return true;
  }

  bool HessianStructure(Index* iRow, Index* jCol) const {
    int e = 0;
    for (int k = 0; k < tr_->NumIntervals(); ++k)
      for (int a = 0; a < kIntervalVars; ++a)
        for (int b = 0; b <= a; ++b, ++e) {
          iRow[e] = tr_->IntervalVar(k, a);
          jCol[e] = tr_->IntervalVar(k, b);
        }
    for (int k = 1; k < tr_->NumIntervals() && NumRatePairs() > 0; ++k)
      for (int i = 0; i < kNumControls; ++i) {
        const int a = tr_->Control(k - 1, i), b = tr_->Control(k, i);
        iRow[e] = jCol[e] = a;
        ++e;
        iRow[e] = jCol[e] = b;
        ++e;
        iRow[e] = b;
        jCol[e] = a;
        ++e;
      }
    for (int k = 1; k <= tr_->NumIntervals() && tr_->node_constraints; ++k)
      for (int a = 0; a < kNumStates; ++a)
        for (int b = 0; b <= a; ++b, ++e) {
          iRow[e] = tr_->State(k, a);
          jCol[e] = tr_->State(k, b);
        }
    return true;
  }

  const Transcription* tr_;
  MidCache cache_;
  std::vector<double> start_;
  std::vector<double> x_final_, lambda_final_;
};

// Whether the row of state bound j (IsStateBound) at midpoint k is implied by the bounds of
// the interval's nodes (the start state's value at node 0): its midpoint bound is at least as
// wide as the mean of theirs.
bool MidBoundImplied(const Vehicle& v, const Transcription& tr, int k, int j,
                     const StateVector<double>& start) {
  const StateBound mid = StateBoundOf(v, j, tr.mids[k].road);
  const double first = k == 0 ? start[mid.state] : StateBoundOf(v, j, tr.nodes[k].road).value;
  const double mean = 0.5 * (first + StateBoundOf(v, j, tr.nodes[k + 1].road).value);
  const double slack = 1e-12 * std::max(1.0, std::abs(mid.value));
  return mid.upper ? mean <= mid.value + slack : mean >= mid.value - slack;
}

// The rows and bounds of the path constraints (Transcription::mid_first).
void PlaceConstraints(const Vehicle& v, const StateVector<double>& start, Transcription* tr) {
  tr->mid_first = {0};
  for (int k = 0; k < tr->NumIntervals(); ++k) {
    for (int j = 0; j < kNumConstraints; ++j)
      if (!tr->node_constraints || !IsStateBound(j) || !MidBoundImplied(v, *tr, k, j, start))
        tr->mid_kind.push_back(j);
    tr->mid_first.push_back(static_cast<int>(tr->mid_kind.size()));
  }
  tr->lower.assign(tr->NumVars(), -kNoBound);
  tr->upper.assign(tr->NumVars(), kNoBound);
  for (int k = 1; k < tr->NumNodes() && tr->node_constraints; ++k)
    for (int j = 0; j < kNumConstraints; ++j) {
      if (!IsStateBound(j)) continue;
      const StateBound b = StateBoundOf(v, j, tr->nodes[k].road);
      const int var = tr->State(k, b.state);
      const double value = b.value / tr->sc.state[b.state];
      if (b.upper) tr->upper[var] = std::min(tr->upper[var], value);
      else tr->lower[var] = std::max(tr->lower[var], value);
    }
}

Transcription MakeTranscription(const Vehicle& v, const RoadTrack& road,
                                const std::vector<double>& mesh, const StateVector<double>& start,
                                const IpoptOptions& options) {
  Transcription tr;
  tr.s = mesh;
  tr.sc = DefaultScales(v);
  tr.rate_weight = options.control_rate_weight;
  tr.threads = options.num_threads;
  tr.node_constraints = options.node_constraints;
  for (int k = 0; k + 1 < tr.NumNodes(); ++k) {
    tr.h.push_back(mesh[k + 1] - mesh[k]);
    tr.mids.push_back({&v, tr.sc, road.At(0.5 * (mesh[k] + mesh[k + 1]))});
  }
  for (double s_k : mesh) tr.nodes.push_back({&v, tr.sc, road.At(s_k)});
  PlaceConstraints(v, start, &tr);
  return tr;
}

// Control i of interval k in the guess: the interval's own, or the mean of its nodes' (as the
// indirect solver starts its controls).
double IntervalControl(const SolverGuess& guess, int k, int i) {
  return guess.u_interval.empty() ? 0.5 * (guess.u[k][i] + guess.u[k + 1][i]) : guess.u_interval.at(k)[i];
}

// The guess as Ipopt's unknowns: x~_k = x_k / S at the nodes, u~_k = IntervalControl / S_u.
std::vector<double> ScaledGuess(const Transcription& tr, const SolverGuess& guess) {
  std::vector<double> z(tr.NumVars());
  for (int k = 0; k < tr.NumNodes(); ++k)
    for (int i = 0; i < kNumStates; ++i) z[tr.State(k, i)] = guess.x[k][i] / tr.sc.state[i];
  for (int k = 0; k < tr.NumIntervals(); ++k)
    for (int i = 0; i < kNumControls; ++i) z[tr.Control(k, i)] = IntervalControl(guess, k, i) / tr.sc.control[i];
  return z;
}

// Ipopt rejects an option value outside its range (tol <= 0, say) by returning false and
// carrying on with its default; here that is an error.
void Require(bool accepted, const char* option) {
  if (!accepted) throw std::invalid_argument(std::string("Ipopt rejected the value of option ") + option);
}

// IpoptOptions::extra: the value read as the option's registered type.
void SetByName(Ipopt::IpoptApplication& app, const std::string& name, const std::string& value) {
  const Ipopt::SmartPtr<const Ipopt::RegisteredOption> option = app.RegOptions()->GetOption(name);
  if (!Ipopt::IsValid(option)) throw std::invalid_argument("Ipopt has no option " + name);
  Ipopt::OptionsList& options = *app.Options();
  const auto parsed = [&](auto number, const char* expected) {
    if (number) return *number;
    throw std::invalid_argument("Ipopt option " + name + ": value '" + value + "' is not " + expected);
  };
  bool accepted = false;
  switch (option->Type()) {
    case Ipopt::OT_Number:
      accepted = options.SetNumericValue(name, parsed(ParseDouble(value), "a number"));
      break;
    case Ipopt::OT_Integer:
      accepted = options.SetIntegerValue(name, parsed(ParseInt(value), "an integer"));
      break;
    default: accepted = options.SetStringValue(name, value);
  }
  Require(accepted, (name + " (" + value + ")").c_str());
}

Ipopt::SmartPtr<Ipopt::IpoptApplication> MakeApplication(const IpoptOptions& o) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& options = *app->Options();
  // Ipopt would read an options file "ipopt.opt" from the working directory and let it override
  // the options below: a stray one would change every lap silently.
  Require(options.SetStringValue("option_file_name", ""), "option_file_name");
  Require(options.SetIntegerValue("print_level", o.print_level), "print_level");
  if (o.print_level == 0) Require(options.SetStringValue("sb", "yes"), "sb");  // no banner
  Require(options.SetStringValue("hessian_approximation", "exact"), "hessian_approximation");
  Require(options.SetStringValue("mu_strategy", o.mu_strategy), "mu_strategy");
  Require(options.SetNumericValue("mu_init", o.mu_init), "mu_init");
  Require(options.SetStringValue("adaptive_mu_globalization", o.mu_globalization),
          "adaptive_mu_globalization");
  Require(options.SetStringValue("linear_solver", "mumps"), "linear_solver");
  // The state bounds (Transcription): Ipopt relaxes every bound by 1e-8 of its value and would
  // clip its answer back onto the original bounds, moving a state that rides its limit (the roll
  // rate) off the solution of the defects: scaled defects of 1e-7 on the first 5 km of the course
  // and 1.03e-6 on the whole course (over the answer check's 1e-6) where Ipopt's own constraint
  // violation was 6e-10. Its answer, unclipped, lies within 1e-8 of the bounds.
  Require(options.SetStringValue("honor_original_bounds", "no"), "honor_original_bounds");
  // A bound's multiplier starts at mu / slack, not 1: with 1, the first barrier weight follows
  // from slacks of up to ~30 in the scaled states (the brake torque's bound) and came out near 2.5,
  // which took a 50 m straight (ipopt_direct_test) into 3000 iterations of restoration.
  Require(options.SetStringValue("bound_mult_init_method", "mu-based"), "bound_mult_init_method");
  Require(options.SetNumericValue("tol", o.tolerance), "tol");
  Require(options.SetIntegerValue("max_iter", o.max_iterations), "max_iter");
  for (const auto& [name, value] : o.extra) SetByName(*app, name, value);
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

// The costates of the scaled states at the nodes. With the Lagrangian
// t + sum_k lambda_k^T c_k + sum_k mu_k^T g_k, stationarity in x~_k reads
//   -lambda_{k-1} - D_{k-1} / 2 = -lambda_k + D_k / 2 =: p_k,
// D_k = d/dx~_mid (h_k / sdot - h_k lambda_k^T x~' + mu_k^T g) at midpoint k. Then
// p_{k+1} - p_k = -D_k with p_{k+1/2} = (p_k + p_{k+1}) / 2 = -lambda_k: the implicit-midpoint
// costate equation of the indirect solver, lambda~_{k+1} - lambda~_k = -h H_x~(k+1/2), exactly,
// and p_N = 0 (free end state). p_k is taken from interval k (k < N), p_N from interval N - 1.
std::vector<StateVector<double>> CostatesFromMultipliers(const Transcription& tr,
                                                         const MidCache& cache,
                                                         const std::vector<double>& lambda) {
  const int n = tr.NumNodes();
  std::vector<StateVector<double>> p(n);
  for (int k = 0; k < tr.NumIntervals(); ++k) {
    const NodeOutputs w = IntervalWeights(tr, k, 1.0, lambda.data());
    const Eigen::Matrix<double, kNodeVars, 1> D = cache.J(k).transpose() * w;
    for (int i = 0; i < kNumStates; ++i) {
      const double mid = -lambda[tr.DefectRow(k, i)];
      p[k][i] = mid + 0.5 * D(i);
      if (k + 1 == tr.NumIntervals()) p[k + 1][i] = mid - 0.5 * D(i);
    }
  }
  return p;
}

// Fills the solution and the checks of the answer (state defects, constraint violations at the
// midpoints and, with node constraints, the nodes) from the cached midpoint values at the final point. The nodes report NodeControls of
// the intervals' controls (solution.h), as the indirect solver.
void CheckAnswer(const Transcription& tr, const std::vector<double>& x, const MidCache& cache,
                 LapSolution* sol, SolveSummary* summary) {
  const int n = tr.NumNodes();
  sol->x.resize(n);
  sol->u_interval.resize(n - 1);
  sol->t.assign(n, 0.0);
  summary->max_violation.assign(kNumConstraints, -HUGE_VAL);
  summary->max_state_defect = 0.0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < kNumStates; ++i) sol->x[k][i] = x[tr.State(k, i)] * tr.sc.state[i];
  for (int k = 0; k + 1 < n; ++k) {
    for (int i = 0; i < kNumControls; ++i)
      sol->u_interval[k][i] = x[tr.Control(k, i)] * tr.sc.control[i];
    for (int j = 0; j < kNumConstraints; ++j) {
      summary->max_violation[j] = std::max(summary->max_violation[j], cache.y(k)(kOutG + j));
      if (tr.node_constraints)
        summary->max_violation[j] = std::max(summary->max_violation[j], cache.g(k + 1)(j));
    }
    sol->t[k + 1] = sol->t[k] + tr.h[k] * cache.y(k)(kOutTime);
    for (int i = 0; i < kNumStates; ++i) {
      const double defect =
          x[tr.State(k + 1, i)] - x[tr.State(k, i)] - tr.h[k] * cache.y(k)(kOutDxDs + i);
      summary->max_state_defect = std::max(summary->max_state_defect, std::abs(defect));
    }
  }
  sol->u = NodeControls(sol->u_interval);
  sol->lap_time = sol->lap_time_extrapolated = sol->t.back();
}

}  // namespace

LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh,
                             const std::vector<StateVector<double>>& x_guess,
                             const std::vector<ControlVector<double>>& u_guess,
                             const IpoptOptions& options, SolveSummary* summary) {
  return SolveDirectIpopt(v, road, mesh, SolverGuess{x_guess, {}, u_guess, {}}, options, summary);
}

LapSolution SolveDirectIpopt(const Vehicle& v, const RoadTrack& road,
                             const std::vector<double>& mesh, const SolverGuess& guess,
                             const IpoptOptions& options, SolveSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  // First, so that an option Ipopt rejects fails before the transcription is built.
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = MakeApplication(options);
  const Transcription tr = MakeTranscription(v, road, mesh, guess.x.at(0), options);
  LapNlp* nlp = new LapNlp(&tr, ScaledGuess(tr, guess));
  const Ipopt::SmartPtr<Ipopt::TNLP> owner = nlp;  // Ipopt's reference counting frees it
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
  MidCache cache(&tr);
  if (nlp->x_final().empty() || !cache.Update(nlp->x_final().data(), true, true)) {
    why << "no answer to check (model undefined at Ipopt's last point); ";
  } else {
    CheckAnswer(tr, nlp->x_final(), cache, &sol, summary);
    sol.lambda = CostatesFromMultipliers(tr, cache, nlp->lambda_final());
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
