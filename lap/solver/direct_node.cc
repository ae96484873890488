#include "lap/solver/direct_node.h"

#include <array>
#include <cmath>

#include "lap/model/cost.h"
#include "lap/model/scalar.h"

namespace ttz::lap {
namespace {

template <typename T>
using Outputs = std::array<T, kNumNodeOutputs>;

// y(z) in any scalar type (double, Jet, nested Jet); false where the model is undefined.
template <typename T>
bool Evaluate(const DirectNode& node, const std::array<T, kNodeVars>& z, Outputs<T>* y) {
  StateVector<T> x;
  ControlVector<T> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = z[i] * node.sc.state[i];
  for (int i = 0; i < kNumControls; ++i) u[i] = z[kNumStates + i] * node.sc.control[i];
  if (!(Val(x[kV]) > 0.1) || !(1.0 - Val(x[kN]) * node.road.kappa > 0.05)) return false;
  const ModelPoint<T> m = EvaluateModel(*node.v, x, u, node.road);
  const ConstraintVector<T> g = EvaluateConstraints(*node.v, x, u, node.road, m);
  if (!(Val(m.kin.sdot) > 0.0)) return false;
  for (int i = 0; i < kNumStates; ++i) (*y)[kOutDxDs + i] = m.dx_ds[i] / node.sc.state[i];
  (*y)[kOutTime] = 1.0 / m.kin.sdot;  // eq. 37: dt/ds
  (*y)[kOutEffort] = EffortPerMetre(*node.v, u, m);
  for (int j = 0; j < kNumConstraints; ++j) (*y)[kOutG + j] = g[j];
  for (const T& yi : *y)
    if (!std::isfinite(Val(yi))) return false;
  return true;
}

}  // namespace

bool NodeValues(const DirectNode& node, const NodePoint& z, NodeOutputs* y) {
  std::array<double, kNodeVars> zz;
  for (int i = 0; i < kNodeVars; ++i) zz[i] = z(i);
  Outputs<double> out;
  if (!Evaluate(node, zz, &out)) return false;
  for (int o = 0; o < kNumNodeOutputs; ++o) (*y)(o) = out[o];
  return true;
}

bool NodeDerivatives(const DirectNode& node, const NodePoint& z, NodeOutputs* y, NodeJacobian* J) {
  using J1 = ceres::Jet<double, kNodeVars>;
  std::array<J1, kNodeVars> zz;
  for (int i = 0; i < kNodeVars; ++i) zz[i] = J1(z(i), i);
  Outputs<J1> out;
  if (!Evaluate(node, zz, &out)) return false;
  for (int o = 0; o < kNumNodeOutputs; ++o) {
    (*y)(o) = out[o].a;
    J->row(o) = out[o].v.transpose();
  }
  return J->allFinite();
}

bool NodeWeightedHessian(const DirectNode& node, const NodePoint& z, const NodeOutputs& w,
                         NodeHessian* H) {
  using J1 = ceres::Jet<double, kNodeVars>;
  using J2 = ceres::Jet<J1, kNodeVars>;
  std::array<J2, kNodeVars> zz;
  for (int i = 0; i < kNodeVars; ++i) zz[i] = J2(J1(z(i), i), i);
  Outputs<J2> out;
  if (!Evaluate(node, zz, &out)) return false;
  J2 sum = Cst<J2>(0.0);
  for (int o = 0; o < kNumNodeOutputs; ++o)
    if (w(o) != 0.0) sum = sum + w(o) * out[o];
  for (int a = 0; a < kNodeVars; ++a)
    for (int b = 0; b < kNodeVars; ++b) (*H)(a, b) = sum.v[a].v[b];
  return H->allFinite();
}

}  // namespace ttz::lap
