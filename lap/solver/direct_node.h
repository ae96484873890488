// One interval midpoint of the direct transcription (lap/solver/ipopt_direct.h): at the
// midpoint's scaled states and the interval's controls z = (x~, u~) = (x / S, u / S_u), the
// quantities the transcription is built from,
//
//   y(z) = ( x~' = x' / S  (eq. 36-37, lap/model/dynamics.h),
//            1 / sdot      (the time per metre of the objective, eq. 37-38),
//            (c_y (dOmega_z/dt)^2 + c_t (dtau_w/dt)^2) / sdot (the effort of the objective, cost.h),
//            g_j(x)        (eq. 39a-g, the voltage limits and the brake bound, constraints.h) ),
//
// their Jacobian dy/dz by Jets, and the Hessian of any weighted sum w^T y by HyperDual (the
// interval's share of the Hessian of the Lagrangian, before the chain factors of
// x~_mid = (x~_k + x~_{k+1}) / 2).
#pragma once

#include <Eigen/Core>

#include "lap/model/constraints.h"
#include "lap/model/road_point.h"
#include "lap/model/vehicle.h"
#include "lap/solver/hamiltonian.h"

namespace ttz::lap {

inline constexpr int kNodeVars = kNumStates + kNumControls;  // z = (x~, u~)

// Positions in y: x~' first, then 1 / sdot and the steering effort, then the constraints.
inline constexpr int kOutDxDs = 0;
inline constexpr int kOutTime = kNumStates;
inline constexpr int kOutEffort = kNumStates + 1;
inline constexpr int kOutG = kNumStates + 2;
inline constexpr int kNumNodeOutputs = kOutG + kNumConstraints;

using NodePoint = Eigen::Matrix<double, kNodeVars, 1>;
using NodeOutputs = Eigen::Matrix<double, kNumNodeOutputs, 1>;
using NodeJacobian = Eigen::Matrix<double, kNumNodeOutputs, kNodeVars, Eigen::RowMajor>;
using NodeHessian = Eigen::Matrix<double, kNodeVars, kNodeVars>;

// The model's data at one point (the road at the interval midpoint s_{k+1/2}).
struct DirectNode {
  const Vehicle* v;
  Scales sc;
  RoadPoint road;
};

// y(z). False where the model is undefined (V <= 0.1 m/s, 1 - n kappa <= 0.05, sdot <= 0 or a
// non-finite value).
bool NodeValues(const DirectNode& node, const NodePoint& z, NodeOutputs* y);

// y(z) and dy/dz.
bool NodeDerivatives(const DirectNode& node, const NodePoint& z, NodeOutputs* y, NodeJacobian* J);

// d2(w^T y)/dz2 (symmetric, both triangles filled).
bool NodeWeightedHessian(const DirectNode& node, const NodePoint& z, const NodeOutputs& w,
                         NodeHessian* H);

// The constraints at a mesh node, g(x~) of the node's scaled state alone (constraints.h,
// StateConstraints; the road at the node): the transcription checks them at the nodes as well as
// at the midpoints (ipopt_direct.h), with their Jacobian by Jets and the Hessian of a weighted sum
// by HyperDual.
using StatePoint = Eigen::Matrix<double, kNumStates, 1>;
using NodeConstraintValues = Eigen::Matrix<double, kNumConstraints, 1>;
using NodeConstraintJacobian = Eigen::Matrix<double, kNumConstraints, kNumStates, Eigen::RowMajor>;
using StateHessian = Eigen::Matrix<double, kNumStates, kNumStates>;

// g(x~) and dg/dx~; false where the model is undefined (V <= 0.1 m/s or a non-finite value).
bool NodeConstraints(const DirectNode& node, const StatePoint& x, NodeConstraintValues* g,
                     NodeConstraintJacobian* J);

// d2(w^T g)/dx~2 (symmetric, both triangles filled).
bool NodeConstraintsWeightedHessian(const DirectNode& node, const StatePoint& x,
                                    const NodeConstraintValues& w, StateHessian* H);

}  // namespace ttz::lap
