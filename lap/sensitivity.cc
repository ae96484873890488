#include "lap/sensitivity.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include "lap/model/vehicle.h"
#include "lap/qss.h"
#include "lap/solver/hamiltonian.h"
#include "lap/solver/node_barrier.h"
#include "lap/solver/parallel.h"
#include "lap/solver/solution_curve.h"
#include "lap/solver/transcription.h"

namespace ttz::lap {
namespace {

constexpr double kRelativeStep = 1e-6;   // of the value (absolute where it is 0)
constexpr size_t kStartNodes = 3;        // of the mesh, for the start state (StartState)
constexpr double kRebuiltResidual = 1e-6;  // largest |residual| of the rebuilt transcription
constexpr double kCelsiusZero = 273.15;  // [K]
// The rider's effort weights c_y, c_t, c_r (lap/model/cost.h): their dJ/dp is no lap time.
constexpr const char* kEffortWeights[] = {"limits.yaw_acceleration_weight_s4_per_rad2",
                                          "limits.torque_rate_weight_s3_per_n2_m2",
                                          "limits.roll_rate_weight_s2_per_rad2"};

// The values that are not "design" (SensitivityKind, sensitivity.h), by kind.
constexpr const char* kRiderKeys[] = {"limits.roll_rate_max_rad_per_s", "limits.yaw_rate_max_rad_per_s",
                                      "limits.border_margin_m"};
constexpr const char* kConditionKeys[] = {"aero.air_density_kg_per_m3", "environment.gravity_m_per_s2",
                                          "environment.ambient_temperature_c", "initial.speed_m_per_s",
                                          "initial.motor_temperature_c", "initial.state_of_charge"};
constexpr const char* kReferenceKeys[] = {"motor.reference_temperature_c"};

template <size_t N>
bool OneOf(const std::string& key, const char* const (&keys)[N]) {
  return std::find(std::begin(keys), std::end(keys), key) != std::end(keys);
}

// The bike's start state: the quasi-steady state at its initial speed, motor temperature and
// charge on the centre line (sensitivity.h).
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
  for (int k = 1; k < tr.NumNodes(); ++k)
    sum += NodeBarrierValue(v, tr.sc, tr.road_nodes[k], tr.NodeWeight(), tr.NodeLength(k), tr.NodeState(k));
  for (int i = 0; i < kNumStates; ++i) sum += tr.W(0)[kNumStates + i] * x0[i] / tr.sc.state[i];
  return sum;
}

// What 1 % of the value `x` of `key` is (sensitivity.h, DesignSensitivity::per_percent).
double OnePercent(const std::string& key, double x) {
  const bool celsius = key.size() > 2 && key.compare(key.size() - 2, 2, "_c") == 0;
  return 0.01 * (celsius ? x + kCelsiusZero : x);
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
  return {key, SensitivityKind(key), x, per_unit, per_unit * OnePercent(key, x)};
}

}  // namespace

std::vector<std::string> SensitivityKeys() {
  std::vector<std::string> keys = RealBikeKeys();
  for (const char* weight : kEffortWeights) keys.erase(std::remove(keys.begin(), keys.end(), weight), keys.end());
  return keys;
}

const char* SensitivityKind(const std::string& key) {
  if (OneOf(key, kRiderKeys)) return "rider";
  if (OneOf(key, kConditionKeys)) return "condition";
  if (OneOf(key, kReferenceKeys)) return "reference";
  return "design";
}

bool HasSensitivities(const LapSolution& sol) {
  const size_t n = sol.s.size();
  return sol.eps > 0.0 && n >= 2 && sol.x.size() == n && sol.lambda.size() == n && sol.u.size() == n &&
         sol.u_interval.size() + 1 == n;
}

std::vector<DesignSensitivity> DesignSensitivities(const BikeParams& bike, const RoadTrack& road,
                                                   const LapSolution& sol, int threads, std::string* why_not) {
  if (!HasSensitivities(sol)) {
    *why_not = "the lap has no barrier costates (eps = 0: an Ipopt lap)";
    return {};
  }
  const Vehicle v = MakeVehicle(bike);
  Transcription tr = MakeTranscription(v, road, sol.s, sol.x, sol.lambda, sol.u, threads);
  tr.weight = WeightFor(sol.eps);
  tr.StartControlsAt(sol.u_interval);  // the Newtons for u~* start at the intervals' own
  double max_residual = 0.0, max_defect = 0.0;
  ResidualLevels(&tr, &max_residual, &max_defect);  // also the node barriers' gradients and u~*
  if (!(max_residual <= kRebuiltResidual)) {
    std::ostringstream o;
    o << "the lap is not the solution of its transcription rebuilt for this bike and road (max |residual| "
      << max_residual << ")";
    *why_not = o.str();
    return {};
  }
  const std::vector<double> start_mesh(sol.s.begin(), sol.s.begin() + std::min(sol.s.size(), kStartNodes));
  const std::vector<std::string> keys = SensitivityKeys();
  std::vector<DesignSensitivity> out(keys.size());
  ForEachInterval(static_cast<int>(keys.size()), threads, [&](int i) {
    out[i] = Sensitivity(bike, tr, road, start_mesh, keys[i]);
    return true;
  });
  return out;
}

}  // namespace ttz::lap
