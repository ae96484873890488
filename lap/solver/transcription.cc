#include "lap/solver/transcription.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "lap/solver/parallel.h"

namespace ttz::lap {

double Transcription::NodeLength(int k) const {
  return 0.5 * ((k > 0 ? H(k - 1) : 0.0) + (k + 1 < NumNodes() ? H(k) : 0.0));
}

StateVector<double> Transcription::MidState(int k) const {
  StateVector<double> xs;
  for (int i = 0; i < kNumStates; ++i) xs[i] = 0.5 * (W(k)[i] + W(k + 1)[i]);
  return xs;
}

StateVector<double> Transcription::NodeState(int k) const {
  StateVector<double> xs;
  std::copy(W(k), W(k) + kNumStates, xs.begin());
  return xs;
}

StateVector<double> Transcription::MidCostate(int k) const {
  StateVector<double> mu;
  for (int i = 0; i < kNumStates; ++i) {
    mu[i] = 0.5 * (W(k)[kNumStates + i] + W(k + 1)[kNumStates + i]);
    if (node_barriers)
      mu[i] += 0.5 * (RightShare(k) * nodes[k + 1].grad(i) - LeftShare(k) * nodes[k].grad(i));
  }
  return mu;
}

Vehicle Transcription::ModelAtWeight() const {
  Vehicle model = *v;
  if (current_widening > 1.0)
    model.smoothing.current *= std::clamp(weight.eps / current_model_eps, 1.0, current_widening);
  return model;
}

void Transcription::EvaluateMids(bool jacobians) {
  const int n = NumNodes() - 1;
  const BarrierWeight mid_weight = MidpointWeight(), node_weight = NodeWeight();
  const Vehicle model = ModelAtWeight();
  if (node_barriers)
    ForEachInterval(n, threads, [&](int k) {
      EvaluateNodeBarrier(model, sc, road_nodes[k + 1], node_weight, NodeLength(k + 1), NodeState(k + 1), jacobians,
                          &nodes[k + 1]);
      return true;  // validity is read from the nodes below
    });
  ForEachInterval(n, threads, [&](int k) {
    EvaluateNode(model, sc, road[k], mid_weight, MidState(k), MidCostate(k), jacobians, &mids[k]);
    return true;  // validity is read from the midpoints below
  });
  all_valid = std::all_of(mids.begin(), mids.end(), [](const NodeData& d) { return d.valid; }) &&
              (!node_barriers || std::all_of(nodes.begin() + 1, nodes.end(),
                                             [](const NodeBarrierData& d) { return d.valid; }));
}

double Transcription::LapTime() const {
  double t = 0.0;
  for (int k = 0; k + 1 < NumNodes(); ++k) t += H(k) * mids[k].dt_ds;
  return t;
}

Transcription MakeTranscription(const Vehicle& v, const RoadTrack& road,
                                const std::vector<double>& mesh,
                                const std::vector<StateVector<double>>& x_guess,
                                const std::vector<StateVector<double>>& lambda_guess,
                                const std::vector<ControlVector<double>>& u_guess, int threads,
                                bool node_barriers) {
  Transcription tr;
  tr.node_barriers = node_barriers;
  tr.v = &v;
  tr.sc = DefaultScales(v);
  tr.s = mesh;
  tr.threads = threads;
  const int n = tr.NumNodes();
  tr.road.resize(n - 1);
  tr.mids.resize(n - 1);
  tr.nodes.resize(n);
  tr.nodes[0].valid = true;
  tr.nodes[0].grad.setZero();
  tr.nodes[0].hess.setZero();
  for (int k = 0; k < n; ++k) tr.road_nodes.push_back(road.At(mesh[k]));
  tr.w.assign(static_cast<size_t>(n) * kW, 0.0);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < kNumStates; ++i) {
      tr.W(k)[i] = x_guess[k][i] / tr.sc.state[i];
      tr.W(k)[kNumStates + i] = lambda_guess.empty() ? 0.0 : lambda_guess[k][i];
    }
  for (int k = 0; k + 1 < n; ++k) {
    tr.road[k] = road.At(0.5 * (mesh[k] + mesh[k + 1]));
    for (int i = 0; i < kNumControls; ++i)
      tr.mids[k].u_start[i] = 0.5 * (u_guess[k][i] + u_guess[k + 1][i]) / tr.sc.control[i];
  }
  return tr;
}

bool IntervalResidual::Evaluate(const double* const* p, double* r, double** J) const {
  const NodeData& d = tr_->mids[k_];
  if (!d.valid) return false;
  const double h = tr_->H(k_);
  // The barriers of the interval's two nodes and the interval's shares in them.
  const double share[2] = {tr_->LeftShare(k_), tr_->RightShare(k_)};
  const NodeBarrierData* node[2] = {share[0] > 0.0 ? &tr_->nodes[k_] : nullptr,
                                    share[1] > 0.0 ? &tr_->nodes[k_ + 1] : nullptr};
  for (const NodeBarrierData* b : node)
    if (b != nullptr && !b->valid) return false;
  for (int i = 0; i < kNumStates; ++i) {
    r[i] = p[1][i] - p[0][i] - h * d.F(i);
    r[kNumStates + i] = p[1][kNumStates + i] - p[0][kNumStates + i] + h * d.G(i);
    for (int side = 0; side < 2; ++side)
      if (node[side] != nullptr) r[kNumStates + i] += share[side] * node[side]->grad(i);
  }
  if (J == nullptr) return true;
  // Both nodes enter the midpoint with weight 1/2; a node's barrier also shifts the midpoint's
  // costate mu~ by -/+ share/2 dB/dx~ (transcription.h).
  for (int side = 0; side < 2; ++side) {
    if (J[side] == nullptr) continue;
    const double sign = side == 0 ? -1.0 : 1.0;
    Eigen::Map<Eigen::Matrix<double, kW, kW, Eigen::RowMajor>> M(J[side]);
    M.topLeftCorner<kNumStates, kNumStates>() = -0.5 * h * d.dF_dx;
    M.topRightCorner<kNumStates, kNumStates>() = -0.5 * h * d.dF_dl;
    M.bottomLeftCorner<kNumStates, kNumStates>() = 0.5 * h * d.dG_dx;
    M.bottomRightCorner<kNumStates, kNumStates>() = 0.5 * h * d.dG_dl;
    M.diagonal().array() += sign;
    if (node[side] != nullptr) {
      const NodeMatrix dmu_dx = (0.5 * sign * share[side]) * node[side]->hess;
      M.topLeftCorner<kNumStates, kNumStates>() -= h * d.dF_dl * dmu_dx;
      M.bottomLeftCorner<kNumStates, kNumStates>() +=
          h * d.dG_dl * dmu_dx + share[side] * node[side]->hess;
    }
  }
  return true;
}

void BuildProblem(Transcription* tr, ceres::Problem* problem) {
  const int n = tr->NumNodes();
  for (int k = 0; k + 1 < n; ++k)
    problem->AddResidualBlock(new IntervalResidual(tr, k), nullptr, tr->W(k), tr->W(k + 1));
  std::vector<int> first_states(kNumStates), last_costates(kNumStates);
  for (int i = 0; i < kNumStates; ++i) {
    first_states[i] = i;
    last_costates[i] = kNumStates + i;
  }
  problem->SetManifold(tr->W(0), new ceres::SubsetManifold(kW, first_states));
  for (int i = kNumStates; i < kW; ++i) tr->W(n - 1)[i] = 0.0;
  tr->W(n - 1)[kNumStates + kE] = -tr->end_charge_price * tr->sc.state[kE];
  problem->SetManifold(tr->W(n - 1), new ceres::SubsetManifold(kW, last_costates));
}

void ResidualLevels(Transcription* tr, double* max_all, double* max_state, ResidualPeak* peak) {
  tr->EvaluateMids(false);
  *max_all = *max_state = tr->all_valid ? 0.0 : HUGE_VAL;
  ResidualPeak where;
  if (tr->all_valid)
    for (int k = 0; k + 1 < tr->NumNodes(); ++k) {
      IntervalResidual res(tr, k);
      double r[kW];
      const double* p[2] = {tr->W(k), tr->W(k + 1)};
      res.Evaluate(p, r, nullptr);
      for (int i = 0; i < kW; ++i) {
        if (std::abs(r[i]) > *max_all) where = {k, i};
        *max_all = std::max(*max_all, std::abs(r[i]));
        if (i < kNumStates) *max_state = std::max(*max_state, std::abs(r[i]));
      }
    }
  if (peak) *peak = where;
}

std::string DescribePeak(const Transcription& tr, const ResidualPeak& peak) {
  if (peak.interval < 0) return "no valid evaluation";
  const bool state = peak.component < kNumStates;
  std::ostringstream o;
  o << (state ? "the defect of " : "the costate equation of ")
    << kStateNames[state ? peak.component : peak.component - kNumStates] << " on " << tr.s[peak.interval] << "-"
    << tr.s[peak.interval + 1] << " m";
  return o.str();
}

}  // namespace ttz::lap
