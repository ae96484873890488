#include "lap/solver/node.h"

#include <cmath>

#include "lap/model/hyper_dual.h"

namespace ttz::lap {
namespace {

constexpr int kZ = kNumStates + kNumControls;  // (x~, u~)

// H_u and H_uu at fixed states by nested Jets over the two controls.
bool ControlDerivatives(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                        const BarrierWeight& w, const StateVector<double>& xs,
                        const StateVector<double>& lambda, const ControlVector<double>& us,
                        Eigen::Vector2d* Hu, Eigen::Matrix2d* Huu) {
  using J1 = ceres::Jet<double, kNumControls>;
  using J2 = ceres::Jet<J1, kNumControls>;
  StateVector<J2> x;
  ControlVector<J2> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = Cst<J2>(xs[i]);
  for (int i = 0; i < kNumControls; ++i) u[i] = J2(J1(us[i], i), i);
  const J2 h = EvaluateHamiltonian(v, sc, road, w, x, u, lambda).H;
  for (int i = 0; i < kNumControls; ++i) {
    (*Hu)(i) = h.a.v[i];
    for (int j = 0; j < kNumControls; ++j) (*Huu)(i, j) = h.v[i].v[j];
  }
  return Hu->allFinite() && Huu->allFinite();
}

// u~* = argmin H by one Newton step from us. H is quadratic in u~: the yaw acceleration and the
// torque rate enter the state equations affinely (the rates of the states Omega_z and tau_w, and
// dOmega_z/dt in eq. 13a and 16, whose accelerations solve a system linear in it), the rider's
// effort quadratically (lap/model/cost.h), and no constraint (lap/model/constraints.h); test
// NodeTest.HIsQuadraticInTheControls guards that. So the step lands on u* from any start, but for
// the rounding of H_u (where H is nearly flat in a control, ~1e-16 of H_u's terms over that
// control's curvature). H_uu = 2 diag(c_y S_y^2, c_t S_t^2) / sdot is positive definite where
// sdot > 0, both weights being positive (lap/bike.cc); elsewhere the node counts as a control
// failure. Until session 53 a damped Newton with a line search on H took at least two
// evaluations, and the nested-Jet Hamiltonian had 16 % of the windows' samples (perf,
// docs/lap_log.md "Session 53").
bool MinimiseOverControls(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                          const BarrierWeight& w, const StateVector<double>& xs,
                          const StateVector<double>& lambda, ControlVector<double>* us) {
  Eigen::Vector2d Hu;
  Eigen::Matrix2d Huu;
  if (!ControlDerivatives(v, sc, road, w, xs, lambda, *us, &Hu, &Huu)) return false;
  const Eigen::LLT<Eigen::Matrix2d> llt(Huu);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Vector2d step = -llt.solve(Hu);
  if (!step.allFinite()) return false;
  for (int i = 0; i < kNumControls; ++i) (*us)[i] += step(i);
  return true;
}

// First-order Jets over (x~, u~): F and G = H_x~ without their derivatives.
void ValuesOnly(const Vehicle& v, const Scales& sc, const RoadPoint& road, const BarrierWeight& w,
                const StateVector<double>& xs, const StateVector<double>& lambda,
                NodeData* node) {
  using J = ceres::Jet<double, kNumStates>;
  StateVector<J> x;
  ControlVector<J> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = J(xs[i], i);
  for (int i = 0; i < kNumControls; ++i) u[i] = J(node->u[i]);
  const HamiltonianValue<J> hv = EvaluateHamiltonian(v, sc, road, w, x, u, lambda);
  node->dt_ds = hv.dt_ds.a;
  for (int i = 0; i < kNumStates; ++i) {
    node->F(i) = hv.f[i].a;
    node->G(i) = hv.H.v[i];
  }
}

// Second-order automatic differentiation over z = (x~, u~) (HyperDual): F, F_z, H_z and H_zz,
// then the total derivatives through u*.
void WithDerivatives(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                     const BarrierWeight& w, const StateVector<double>& xs,
                     const StateVector<double>& lambda, NodeData* node) {
  using D = HyperDual<kZ>;
  StateVector<D> x;
  ControlVector<D> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = D(xs[i], i);
  for (int i = 0; i < kNumControls; ++i) u[i] = D(node->u[i], kNumStates + i);
  const HamiltonianValue<D> hv = EvaluateHamiltonian(v, sc, road, w, x, u, lambda);
  node->dt_ds = hv.dt_ds.a;
  Eigen::Matrix<double, kNumStates, kZ> Fz;
  Eigen::Matrix<double, kZ, kZ> Hzz;
  for (int i = 0; i < kNumStates; ++i) {
    node->F(i) = hv.f[i].a;
    node->G(i) = hv.H.g[i];
    Fz.row(i) = hv.f[i].g.transpose();
  }
  for (int i = 0; i < kZ; ++i)
    for (int j = 0; j < kZ; ++j) Hzz(i, j) = hv.H.Hessian(i, j);
  const auto Fx = Fz.leftCols<kNumStates>();
  const auto Fu = Fz.rightCols<kNumControls>();
  const auto Hxx = Hzz.topLeftCorner<kNumStates, kNumStates>();
  const auto Hxu = Hzz.topRightCorner<kNumStates, kNumControls>();
  const Eigen::Matrix2d Huu = Hzz.bottomRightCorner<kNumControls, kNumControls>();
  const Eigen::Matrix2d Huu_inv = Huu.inverse();
  // H_u(x, lambda, u*(x, lambda)) = 0: du/dx = -Huu^-1 H_ux, du/dlambda = -Huu^-1 F_u^T.
  node->du_dx = -Huu_inv * Hxu.transpose();
  node->du_dl = -Huu_inv * Fu.transpose();
  const auto& du_dx = node->du_dx;
  const auto& du_dl = node->du_dl;
  node->dF_dx = Fx + Fu * du_dx;
  node->dF_dl = Fu * du_dl;
  node->dG_dx = Hxx + Hxu * du_dx;
  node->dG_dl = Fx.transpose() + Hxu * du_dl;
}

}  // namespace

void EvaluateNode(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                  const BarrierWeight& w, const StateVector<double>& xs,
                  const StateVector<double>& lambda, bool jacobians, NodeData* node) {
  node->valid = false;
  const double V = xs[kV] * sc.state[kV];
  if (!(V > 0.1) || !(1.0 - xs[kN] * sc.state[kN] * road.kappa > 0.05)) return;
  node->u = node->u_start;
  node->control_converged = MinimiseOverControls(v, sc, road, w, xs, lambda, &node->u);
  if (jacobians)
    WithDerivatives(v, sc, road, w, xs, lambda, node);
  else
    ValuesOnly(v, sc, road, w, xs, lambda, node);
  node->valid = std::isfinite(node->dt_ds) && node->dt_ds > 0.0 && node->F.allFinite() &&
                node->G.allFinite() &&
                (!jacobians || (node->dF_dx.allFinite() && node->dF_dl.allFinite() &&
                                node->dG_dx.allFinite() && node->dG_dl.allFinite()));
}

Scales DefaultScales(const Vehicle& v) {
  Scales s;
  s.state = {1.0, 0.1, 10.0, 0.01, 0.01, 0.1, 30.0, 10.0, v.pack.e_i, 0.1, 0.1, 0.1, 100.0};
  s.control = {1.0, 1000.0};
  return s;
}

}  // namespace ttz::lap
