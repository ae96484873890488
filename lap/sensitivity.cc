#include "lap/sensitivity.h"

#include <algorithm>
#include <cmath>

#include "lap/model/vehicle.h"
#include "lap/qss.h"
#include "lap/solver/hamiltonian.h"
#include "lap/solver/node_barrier.h"
#include "lap/solver/parallel.h"
#include "lap/solver/solution_curve.h"
#include "lap/solver/transcription.h"

namespace ttz::lap {
namespace {

constexpr double kRelativeStep = 1e-6;  // of the value (absolute where it is 0)
constexpr size_t kStartNodes = 3;       // of the mesh, for the start state (StartState)

// The bike's start state: the quasi-steady state at its initial speed, motor temperature and
// charge (lap/qss.h), as the solvers' guesses start, on the first nodes of the mesh (the start's
// acceleration is the first interval's).
StateVector<double> StartState(const Vehicle& v, const RoadTrack& road, const std::vector<double>& start_mesh) {
  return ComputeQss(v, road, start_mesh).x.front();
}

// The part of the Lagrangian that depends on the bike (sensitivity.h) for vehicle `v` at the
// answer held in `tr`: sum_k h_k H_k + sum_k B_k + lambda~_0 . x~_0 [s].
double Lagrangian(const Transcription& tr, const Vehicle& v, const StateVector<double>& x0) {
  double sum = 0.0;
  for (int k = 0; k + 1 < tr.NumNodes(); ++k)
    sum += tr.H(k) * EvaluateHamiltonian<double>(v, tr.sc, tr.road[k], tr.MidpointWeight(), tr.MidState(k),
                                                 tr.mids[k].u, tr.MidCostate(k))
                         .H;
  for (int k = 1; tr.node_barriers && k < tr.NumNodes(); ++k) {
    StateVector<double> xs;
    std::copy(tr.W(k), tr.W(k) + kNumStates, xs.begin());
    sum += NodeBarrierValue(v, tr.sc, tr.road_nodes[k], tr.NodeWeight(), tr.NodeLength(k), xs);
  }
  for (int i = 0; i < kNumStates; ++i) sum += tr.W(0)[kNumStates + i] * x0[i] / tr.sc.state[i];
  return sum;
}

// dJ/dp of the value `key` by a central difference of the Lagrangian.
DesignSensitivity Sensitivity(const BikeParams& bike, const Transcription& tr, const RoadTrack& road,
                              const std::vector<double>& start_mesh, const std::string& key) {
  BikeParams p = bike;
  double& value = RealBikeValue(p, key);
  const double x = value, h = x != 0.0 ? kRelativeStep * std::abs(x) : kRelativeStep;
  const auto lagrangian = [&](double at) {
    value = at;
    const Vehicle v = MakeVehicle(p);
    return Lagrangian(tr, v, StartState(v, road, start_mesh));
  };
  const double per_unit = (lagrangian(x + h) - lagrangian(x - h)) / (2.0 * h);
  return {key, x, per_unit, per_unit * x / 100.0};
}

}  // namespace

bool HasSensitivities(const LapSolution& sol) {
  return sol.eps > 0.0 && sol.s.size() >= 2 && sol.lambda.size() == sol.s.size() &&
         sol.x.size() == sol.s.size() && sol.u.size() == sol.s.size();
}

std::vector<DesignSensitivity> DesignSensitivities(const BikeParams& bike, const RoadTrack& road,
                                                   const LapSolution& sol, int threads) {
  if (!HasSensitivities(sol)) return {};
  const Vehicle v = MakeVehicle(bike);
  Transcription tr = MakeTranscription(v, road, sol.s, sol.x, sol.lambda, sol.u, threads);
  tr.weight = WeightFor(sol.eps);
  tr.EvaluateMids(false);  // the node barriers' gradients (MidCostate) and the midpoints' u~*
  const std::vector<double> start_mesh(sol.s.begin(), sol.s.begin() + std::min<size_t>(sol.s.size(), kStartNodes));
  const std::vector<std::string> keys = RealBikeKeys();
  std::vector<DesignSensitivity> out(keys.size());
  ForEachInterval(static_cast<int>(keys.size()), threads, [&](int i) {
    out[i] = Sensitivity(bike, tr, road, start_mesh, keys[i]);
    return true;
  });
  return out;
}

}  // namespace ttz::lap
