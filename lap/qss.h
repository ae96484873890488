// The quasi-steady-state (QSS) lap on the centre line: the speed profile that respects, point by
// point, the lateral adherence in steady cornering, the adherence ellipse when accelerating and
// braking, and the power train's current, voltage and power limits (forward and backward
// integration), and the full model state that goes with it. It is the optimal solver's initial
// guess and its yardstick: the optimal lap can only be faster.
#pragma once

#include <vector>

#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/road_track.h"

namespace ttz::lap {

struct QssLap {
  std::vector<double> s;                   // mesh [m]
  std::vector<double> V;                   // speed [m/s]
  std::vector<double> t;                   // time [s]
  std::vector<StateVector<double>> x;      // model states along the profile
  std::vector<ControlVector<double>> u;    // controls (yaw rate, wheel torque)
  double lap_time = 0.0;                   // [s]
};

// Largest traction force at the wheel [N] the power train gives at speed V, charge e, motor
// temperature T (current, motor-voltage, pack-voltage and pack-power limits; eq. 22-31, 39e-f).
double MaxTractionForce(const Vehicle& v, double V, double e, double T);

QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh);

}  // namespace ttz::lap
