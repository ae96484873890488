// The transcription of the necessary conditions (lap/solver/hamiltonian.h) on an arc-length mesh
// by the implicit midpoint rule, as a square residual system for Ceres: the unknowns are the
// scaled states and costates at the nodes, the Hamiltonian is evaluated at the interval
// midpoints (one control per interval, eliminated there: lap/solver/node.h), and each interval
// contributes one residual block of state and costate defects.
//
// The trapezoidal rule with controls at the nodes sees only the mean of two neighbouring controls,
// so an alternating (odd-even) pattern of controls changes no defect: on the fast wheel-spin and
// roll modes that null direction left Newton stalled (docs/lap.md). The midpoint rule has no such
// direction, and it is symplectic: its costate equations are the exact adjoint of its state
// equations.
#pragma once

#include <ceres/ceres.h>

#include <vector>

#include "lap/road_track.h"
#include "lap/solver/node.h"

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
  BarrierWeight weight{};        // set by the continuation before each solve
  int threads = 1;               // for EvaluateMids
  bool all_valid = false;        // every midpoint valid after the last EvaluateMids

  int NumNodes() const { return static_cast<int>(s.size()); }
  double* W(int k) { return w.data() + k * kW; }
  const double* W(int k) const { return w.data() + k * kW; }
  double H(int k) const { return s[k + 1] - s[k]; }

  // Evaluates every midpoint at (w_k + w_{k+1}) / 2: u*, F, G, and their derivatives if asked.
  void EvaluateMids(bool jacobians);
  // sum_k h_k / sdot_{k+1/2} [s], from the last EvaluateMids.
  double LapTime() const;
  // The controls u* of the last EvaluateMids become the Newton starts of the next ones.
  void KeepControlsAsStarts() {
    for (NodeData& d : mids) d.u_start = d.u;
  }
};

// The transcription of `mesh` for vehicle `v` from a guess: scaled states and costates (zeros
// when `lambda_guess` is empty) at the nodes, control starts at the midpoints.
Transcription MakeTranscription(const Vehicle& v, const RoadTrack& road,
                                const std::vector<double>& mesh,
                                const std::vector<StateVector<double>>& x_guess,
                                const std::vector<StateVector<double>>& lambda_guess,
                                const std::vector<ControlVector<double>>& u_guess, int threads);

// Interval [k, k+1]:  x~_{k+1} - x~_k - h F_{k+1/2} = 0,  lambda~_{k+1} - lambda~_k + h G_{k+1/2} = 0.
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

// One residual block per interval; x(0) and lambda(s_f) = 0 held by SubsetManifolds.
void BuildProblem(Transcription* tr, ceres::Problem* problem);

// Largest |residual| of the system at the current unknowns: of all, and of the state defects.
void ResidualLevels(Transcription* tr, double* max_all, double* max_state);

}  // namespace ttz::lap
