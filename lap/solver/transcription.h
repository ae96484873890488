// The transcription of the necessary conditions (lap/solver/hamiltonian.h) on an arc-length mesh
// by the implicit midpoint rule, as a square residual system for Ceres: the unknowns are the
// scaled states and costates at the nodes, the Hamiltonian is evaluated at the interval
// midpoints (one control per interval, eliminated there: lap/solver/node.h), and each interval
// contributes one residual block of state and costate defects.
//
// With node barriers (node_barrier.h) the costate jumps by -dB_k/dx~_k at node k. The unknown
// lambda~_k is the mean of its left and right limits, lambda~_k -/+ c dB_k/dx~_k with c = 1/2;
// node 0, whose state is fixed, has no barrier, and lambda~_N = 0 is the right limit after the
// last node, so its left limit carries all of dB_N/dx~_N. With a_k = 0 (k = 0) or 1/2 and
// b_k = 1 (k + 1 = N) or 1/2 the interval's costate at its midpoint is
//   mu~_k = (lambda~_k + lambda~_{k+1}) / 2 + (b_k dB_{k+1}/dx~ - a_k dB_k/dx~) / 2
// (the mean of lambda~_k's right limit and lambda~_{k+1}'s left limit), and the costate defect
// gains a_k dB_k/dx~ + b_k dB_{k+1}/dx~. This is the exact adjoint of the midpoint rule with
// sum_k B_k added to the objective.
//
// The trapezoidal rule with controls at the nodes sees only the mean of two neighbouring controls,
// so an alternating (odd-even) pattern of controls changes no defect: on the fast wheel-spin and
// roll modes that null direction left Newton stalled (docs/lap.md). The midpoint rule has no such
// direction, and it is symplectic: its costate equations are the exact adjoint of its state
// equations.
#pragma once

#include <ceres/ceres.h>

#include <string>
#include <vector>

#include "lap/road_track.h"
#include "lap/solver/node.h"
#include "lap/solver/node_barrier.h"

namespace ttz::lap {

constexpr int kW = 2 * kNumStates;  // unknowns per node: scaled states and costates

// The discretised necessary conditions: the unknowns at the nodes, the Hamiltonian's evaluations
// at the interval midpoints and the barrier weight (model and data kept apart: `mids` is the data
// the residual blocks read, refreshed by EvaluateMids).
struct Transcription {
  const Vehicle* v = nullptr;
  Scales sc;
  std::vector<double> s;         // nodes [m]
  std::vector<RoadPoint> road;   // at the interval midpoints
  std::vector<double> w;         // (N + 1) x kW: [x~_k, lambda~_k]
  std::vector<NodeData> mids;    // the N interval midpoints
  bool node_barriers = true;     // barriers at the nodes 1..N too (node_barrier.h)
  std::vector<RoadPoint> road_nodes;      // at the nodes
  std::vector<NodeBarrierData> nodes;     // the N + 1 nodes (node 0's stays zero)
  BarrierWeight weight{};        // set by the continuation before each solve
  // The motor current's smoothing width along the continuation (IndirectOptions::
  // current_widening): the model's width d times clamp(eps / current_model_eps, 1,
  // current_widening) at the weight eps. 1: the model's at every weight.
  double current_widening = 1.0;
  double current_model_eps = 0.0;  // [1]
  // Price on the charge left at s_N [s/J]: the terminal cost -price e(s_N), so that BuildProblem
  // holds lambda~_e(s_N) = -price e_scale (IndirectOptions::end_charge_price_s_per_j).
  double end_charge_price = 0.0;
  int threads = 1;               // for EvaluateMids
  bool all_valid = false;        // every midpoint valid after the last EvaluateMids

  int NumNodes() const { return static_cast<int>(s.size()); }
  double* W(int k) { return w.data() + k * kW; }
  const double* W(int k) const { return w.data() + k * kW; }
  double H(int k) const { return s[k + 1] - s[k]; }
  // The node barriers' share theta of eps (with node barriers on): the midpoints' barriers weigh
  // (1 - theta / 2) eps and the nodes' theta eps / 2. At theta = 1, the answer's, each takes half
  // of eps, so that switching them on leaves the barrier's total about the same (the midpoint and
  // the trapezoidal rule of the same integral, averaged); the first step from a guess switches
  // them on by a continuation in theta from 0 (indirect.cc, NodeBarrierPath).
  double node_share = 1.0;
  BarrierWeight MidpointWeight() const {
    return node_barriers ? BarrierWeight{(1.0 - 0.5 * node_share) * weight.eps, weight.delta}
                         : weight;
  }
  BarrierWeight NodeWeight() const { return {0.5 * node_share * weight.eps, weight.delta}; }
  // Shares a_k and b_k of interval k in the barriers of its left and right nodes (above).
  // l_k [m]: the length of road node k stands for (half of each neighbouring interval).
  double NodeLength(int k) const;
  double LeftShare(int k) const { return k == 0 || !node_barriers ? 0.0 : 0.5; }
  double RightShare(int k) const {
    return !node_barriers ? 0.0 : k + 2 == NumNodes() ? 1.0 : 0.5;
  }

  // The vehicle model at the current weight: *v with the motor current's widened smoothing.
  Vehicle ModelAtWeight() const;
  // Interval k's midpoint: the scaled state (x~_k + x~_{k+1}) / 2, and the costate mu~_k, the mean
  // of the nodes' shifted by the node barriers' gradients of the last EvaluateMids
  // (mu~_k = (lambda~_k + lambda~_{k+1}) / 2 + (b_k dB_{k+1}/dx~ - a_k dB_k/dx~) / 2): the
  // multiplier of the interval's state defect in the discrete problem's Lagrangian.
  StateVector<double> MidState(int k) const;
  StateVector<double> NodeState(int k) const;  // x~_k
  StateVector<double> MidCostate(int k) const;
  // Evaluates the node barriers, then every midpoint at (MidState, MidCostate): u*, F, G, and
  // their derivatives if asked.
  void EvaluateMids(bool jacobians);
  // sum_k h_k / sdot_{k+1/2} [s], from the last EvaluateMids.
  double LapTime() const;
  // The controls u* of the last EvaluateMids become the Newton starts of the next ones.
  void KeepControlsAsStarts() {
    for (NodeData& d : mids) d.u_start = d.u;
  }
  // The intervals' controls of a lap (physical units, one per interval) become the Newton starts.
  void StartControlsAt(const std::vector<ControlVector<double>>& u_interval) {
    for (size_t k = 0; k < mids.size(); ++k)
      for (int i = 0; i < kNumControls; ++i) mids[k].u_start[i] = u_interval[k][i] / sc.control[i];
  }
};

// The transcription of `mesh` for vehicle `v` from a guess: scaled states and costates (zeros
// when `lambda_guess` is empty) at the nodes, control starts at the midpoints.
Transcription MakeTranscription(const Vehicle& v, const RoadTrack& road,
                                const std::vector<double>& mesh,
                                const std::vector<StateVector<double>>& x_guess,
                                const std::vector<StateVector<double>>& lambda_guess,
                                const std::vector<ControlVector<double>>& u_guess, int threads,
                                bool node_barriers = true);

// Interval [k, k+1]:  x~_{k+1} - x~_k - h F_{k+1/2} = 0,
//                    lambda~_{k+1} - lambda~_k + h G_{k+1/2} + a_k dB_k/dx~ + b_k dB_{k+1}/dx~ = 0.
// It reads the midpoint data of the last EvaluateMids (MidpointCallback keeps them current).
class IntervalResidual : public ceres::SizedCostFunction<kW, kW, kW> {
 public:
  IntervalResidual(const Transcription* tr, int k) : tr_(tr), k_(k) {}
  bool Evaluate(const double* const* p, double* r, double** J) const final;

 private:
  const Transcription* tr_;
  int k_;
};

// Ceres calls this before evaluating residuals at a new point: every midpoint is evaluated once.
class MidpointCallback : public ceres::EvaluationCallback {
 public:
  explicit MidpointCallback(Transcription* tr) : tr_(tr) {}
  void PrepareForEvaluation(bool evaluate_jacobians, bool) final {
    tr_->EvaluateMids(evaluate_jacobians);
  }

 private:
  Transcription* tr_;
};

// One residual block per interval; x(0) and lambda(s_f) = dPhi/dx~ (zero but for
// end_charge_price's lambda~_e) held by SubsetManifolds.
void BuildProblem(Transcription* tr, ceres::Problem* problem);

// Where the system's largest |residual| sits: interval [k, k+1] and component i of its block
// (i < kNumStates: the defect of state i; else the costate equation of state i - kNumStates).
struct ResidualPeak {
  int interval = -1;  // -1: no valid evaluation
  int component = -1;
};

// Largest |residual| of the system at the current unknowns: of all, and of the state defects;
// where the largest of all sits if `peak` is given.
void ResidualLevels(Transcription* tr, double* max_all, double* max_state, ResidualPeak* peak = nullptr);

// "the costate equation of V on 20800-20805 m": the peak in words, for a solver's messages.
std::string DescribePeak(const Transcription& tr, const ResidualPeak& peak);

}  // namespace ttz::lap
