#include "lap/solver/direct_node.h"

#include <array>
#include <cmath>

#include "lap/model/cost.h"
#include "lap/model/hyper_dual.h"
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
  (*y)[kOutEffort] = EffortPerMetre(*node.v, x, u, m);
  for (int j = 0; j < kNumConstraints; ++j) (*y)[kOutG + j] = g[j];
  for (const T& yi : *y)
    if (!std::isfinite(Val(yi))) return false;
  return true;
}

// g(x) at a node's scaled state x~ in any scalar type; false where the model is undefined.
template <typename T>
bool EvaluateAtState(const DirectNode& node, const std::array<T, kNumStates>& xs,
                     std::array<T, kNumConstraints>* g) {
  StateVector<T> x;
  for (int i = 0; i < kNumStates; ++i) x[i] = xs[i] * node.sc.state[i];
  if (!(Val(x[kV]) > 0.1)) return false;
  *g = StateConstraints(*node.v, x, node.road);
  for (const T& gj : *g)
    if (!std::isfinite(Val(gj))) return false;
  return true;
}

// The outputs out(z) of eval(z, &out) (M of them, z of size N) and their Jacobian, by Jets.
template <int M, typename F, typename Z, typename Y, typename J>
bool ValuesAndJacobian(F eval, const Z& z, Y* y, J* jac) {
  constexpr int N = Z::RowsAtCompileTime;
  using J1 = ceres::Jet<double, N>;
  std::array<J1, N> zz;
  for (int i = 0; i < N; ++i) zz[i] = J1(z(i), i);
  std::array<J1, M> out;
  if (!eval(zz, &out)) return false;
  for (int o = 0; o < M; ++o) {
    (*y)(o) = out[o].a;
    jac->row(o) = out[o].v.transpose();
  }
  return jac->allFinite();
}

// The Hessian of w^T out(z) by second-order automatic differentiation (HyperDual; both
// triangles filled).
template <int M, typename F, typename Z, typename W, typename H>
bool WeightedHessian(F eval, const Z& z, const W& w, H* hess) {
  constexpr int N = Z::RowsAtCompileTime;
  using D = HyperDual<N>;
  std::array<D, N> zz;
  for (int i = 0; i < N; ++i) zz[i] = D(z(i), i);
  std::array<D, M> out;
  if (!eval(zz, &out)) return false;
  D sum;
  for (int o = 0; o < M; ++o)
    if (w(o) != 0.0) sum += out[o] * w(o);
  for (int a = 0; a < N; ++a)
    for (int b = 0; b <= a; ++b) (*hess)(a, b) = (*hess)(b, a) = sum.h[D::Index(a, b)];
  return hess->allFinite();
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
  return ValuesAndJacobian<kNumNodeOutputs>(
      [&](const auto& zz, auto* out) { return Evaluate(node, zz, out); }, z, y, J);
}

bool NodeWeightedHessian(const DirectNode& node, const NodePoint& z, const NodeOutputs& w,
                         NodeHessian* H) {
  return WeightedHessian<kNumNodeOutputs>(
      [&](const auto& zz, auto* out) { return Evaluate(node, zz, out); }, z, w, H);
}

bool NodeConstraints(const DirectNode& node, const StatePoint& x, NodeConstraintValues* g,
                     NodeConstraintJacobian* J) {
  return ValuesAndJacobian<kNumConstraints>(
      [&](const auto& xx, auto* out) { return EvaluateAtState(node, xx, out); }, x, g, J);
}

bool NodeConstraintsWeightedHessian(const DirectNode& node, const StatePoint& x,
                                    const NodeConstraintValues& w, StateHessian* H) {
  return WeightedHessian<kNumConstraints>(
      [&](const auto& xx, auto* out) { return EvaluateAtState(node, xx, out); }, x, w, H);
}

}  // namespace ttz::lap
