// One mesh node of the indirect transcription: the optimal controls u*(x, lambda) = argmin_u H by
// one Newton step on H_u = 0 (H is quadratic in u), and the node's contribution to the collocation residuals, F = x~' and
// G = H_x~ at u*, with their total derivatives with respect to the node's states and costates
// (through u* by the implicit-function theorem). Second derivatives of H come from HyperDual
// (lap/model/hyper_dual.h; nested Jets over the two controls for the Newton step).
#pragma once

#include <Eigen/Dense>

#include "lap/solver/hamiltonian.h"

namespace ttz::lap {

using NodeMatrix = Eigen::Matrix<double, kNumStates, kNumStates, Eigen::RowMajor>;
using NodeVector = Eigen::Matrix<double, kNumStates, 1>;

struct NodeData {
  bool valid = false;        // model defined (V > 0, 1 - n kappa > 0) and H_uu positive definite
  bool control_converged = false;
  ControlVector<double> u{};        // u~*, scaled controls
  ControlVector<double> u_start{};  // Newton start: u~* of the last accepted iterate
  double dt_ds = 0.0;        // 1 / sdot [s/m]
  NodeVector F, G;           // x~' and H_x~
  NodeMatrix dF_dx, dF_dl, dG_dx, dG_dl;  // total derivatives (Jacobians only)
  Eigen::Matrix<double, kNumControls, kNumStates> du_dx, du_dl;  // of u~* (Jacobians only)
};

// Fills `node` for scaled state xs and costate lambda; the Newton step for u* starts from
// `node->u_start` (u* depends on it only through rounding). Derivatives only when `jacobians`.
void EvaluateNode(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                  const BarrierWeight& w, const StateVector<double>& xs,
                  const StateVector<double>& lambda, bool jacobians, NodeData* node);

}  // namespace ttz::lap
