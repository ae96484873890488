// The quasi-steady-state (QSS) lap on the centre line: the speed profile that respects, node by
// node, the tyre's adherence in steady cornering and when accelerating and braking, the yaw- and
// roll-rate limits, and the power train's current, voltage, power and charge limits with the motor
// temperature and the battery energy integrated along the profile (forward and backward passes),
// and the full model state that goes with it. It is the optimal solver's initial guess and its
// yardstick: on the same mesh, the optimal lap can only be faster (qss.cc lists what makes the QSS
// no faster than the model).
#pragma once

#include <vector>

#include "lap/model/state.h"
#include "lap/model/vehicle.h"
#include "lap/racing_line.h"
#include "lap/road_track.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

struct QssLap {
  std::vector<double> s;                   // mesh [m]
  std::vector<double> V;                   // speed [m/s]
  std::vector<double> t;                   // time [s]
  std::vector<StateVector<double>> x;      // model states along the profile; x[0] is the bike's
                                           // initial state (V0, T0, e0)
  std::vector<ControlVector<double>> u;    // controls (yaw rate, wheel torque)
  double lap_time = 0.0;                   // [s], trapezoidal rule of 1/V (eq. 38; qss.cc)
};

// Largest traction force tau_w / R_e [N] that the power train gives on a straight level road at
// speed V, battery energy e and motor temperature T (current, motor-voltage, pack-voltage and
// pack-power limits, eq. 22-31, 39e-f; and 95 % of the tyre's adherence, eq. 19), upright, with
// the wheel spinning faster than V / R_e by the slip that the tyre force needs (eq. 18, 20) and
// the wheel's spin-up torque (eq. 16) in tau_w.
double MaxTractionForce(const Vehicle& v, double V, double e, double T);

// The QSS lap on `mesh`. x[0] is always the bike's initial state: speed V0, motor temperature T0
// and energy e0, whatever the road; if V0 exceeds what the tyre allows at s = 0 the profile brakes
// to its envelope over the first interval (a start the model cannot hold; the solvers, which fix
// x[0], report the violated constraint).
// When the pack cannot last the lap at full power, the lap is the faster of two: full power until
// the pack is empty, and the pack's power held under one limit for the whole lap, the largest
// that leaves 1 % of the pack at the end (an energy-saving lap, paper sec. 5).
QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh);

// The lap time that a joule more in the pack at the start saves the QSS lap on the centre line
// [s/J]: (T(0.95 e0) - T(e0)) / (0.05 e0) by ComputeQss, `qss` being the caller's ComputeQss(v,
// road, mesh) (T(e0)). About 0 when the pack lasts the lap at full power with 5 % to spare; an
// estimate of the optimal lap's price on charge, lambda_e, where the pack limits the lap (the
// indirect solver's IndirectOptions::window_charge_price_s_per_j).
double QssChargePrice(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                      const QssLap& qss);

// The same on a racing line (racing_line.h) instead of the centre line: each node's quasi-steady
// state on a path of the line's curvature, with the line's offset n and heading alpha (tan of
// alpha + beta = n' / (1 - n kappa), eq. 10) in the states from node 1 on. The indirect solver's
// default initial guess (lap/main.cc, QssStart); the centre line's stays the yardstick. Distances are the road's: the lap
// time ignores the line's own length (within ~n kappa of it).
QssLap ComputeQss(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                  const RacingLine& line);

// A flying lap's start on a closed road (lap --start flying): the speed V0 with which the QSS lap
// on the centre line that starts at V0 arrives back at the line. Found by passes from v's own V0,
// each starting at the speed the one before ended with, until two agree within 1e-3 m/s; after 20
// passes without that, the last end speed, with *settled false (a lap that never brakes ends each
// pass faster, towards its top speed). A lap forgets its start at its first braking point, so on
// a circuit the second pass agrees with the first. The start temperature and charge stay v's in
// every pass. Not the racing line's QSS lap: its line, free at the road's end, swings across the
// road there to straighten its path (on a circle of 40 m radius from the inside to the outside
// border in the last 20 m), so its speed at the end is not the speed at the line.
double PeriodicQssSpeed(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                        bool* settled);

// The QSS lap on the racing line of `mesh` (ComputeRacingLine with the bike's border margin,
// starting at start's offset n) from `start` instead of the bike's initial state: its speed,
// motor temperature and energy start the profile, and x[0] is `start` whole. The guess of a
// window of the indirect solver's first step (QssWindowGuess).
QssLap ComputeQssFrom(const Vehicle& v, const RoadTrack& road, const std::vector<double>& mesh,
                      const StateVector<double>& start);

// ComputeQssFrom as the indirect solver's window guess (IndirectOptions::window_guess); `v` and
// `road` must outlive it.
WindowGuess QssWindowGuess(const Vehicle& v, const RoadTrack& road);

}  // namespace ttz::lap
