// The path constraints (eq. 39a-g, the voltage limits) at a mesh node, as the indirect solver's
// barrier there. The transcription evaluates the Hamiltonian, and with it the constraints, at the
// interval midpoints; a state held at its limit at two midpoints may overshoot it at the node
// between them (docs/lap.md, "Constraints at the nodes"). Every constraint is a function of the
// state alone (lap/model/constraints.h, StateConstraints), so the node carries its own barrier
//
//   B_k(x~_k) = eps l_k sum_j P_delta(g_j(x_k)) / sdot(x_k)        [s]
//
// with l_k the length of road the node stands for (half of each neighbouring interval), the same
// time-weighted relaxed barrier as the midpoints' (lap/solver/hamiltonian.h). It enters the
// costate equations as a jump of lambda~ by -dB_k/dx~_k at the node (lap/solver/transcription.h).
#pragma once

#include "lap/road_track.h"
#include "lap/solver/node.h"

namespace ttz::lap {

struct NodeBarrierData {
  bool valid = false;  // model defined at the node (V > 0.1, 1 - n kappa > 0.05, sdot > 0)
  NodeVector grad;     // dB/dx~
  NodeMatrix hess;     // d2B/dx~2 (only when asked)
};

// Fills `out` for the scaled state xs at a node standing for `length_m` metres of road.
void EvaluateNodeBarrier(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                         const BarrierWeight& w, double length_m, const StateVector<double>& xs,
                         bool hessian, NodeBarrierData* out);

// B itself (the objective's share of the node), for tests and reports.
double NodeBarrierValue(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                        const BarrierWeight& w, double length_m, const StateVector<double>& xs);

}  // namespace ttz::lap
