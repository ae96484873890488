#include "lap/solver/node.h"

#include <cmath>

#include "lap/model/hyper_dual.h"

namespace ttz::lap {
namespace {

constexpr int kZ = kNumStates + kNumControls;  // (x~, u~)

// H, H_u and H_uu at fixed states by nested Jets over the two controls.
bool ControlDerivatives(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                        const BarrierWeight& w, const StateVector<double>& xs,
                        const StateVector<double>& lambda, const ControlVector<double>& us,
                        double* H, Eigen::Vector2d* Hu, Eigen::Matrix2d* Huu) {
  using J1 = ceres::Jet<double, kNumControls>;
  using J2 = ceres::Jet<J1, kNumControls>;
  StateVector<J2> x;
  ControlVector<J2> u;
  for (int i = 0; i < kNumStates; ++i) x[i] = Cst<J2>(xs[i]);
  for (int i = 0; i < kNumControls; ++i) u[i] = J2(J1(us[i], i), i);
  const J2 h = EvaluateHamiltonian(v, sc, road, w, x, u, lambda).H;
  *H = h.a.a;
  for (int i = 0; i < kNumControls; ++i) {
    (*Hu)(i) = h.a.v[i];
    for (int j = 0; j < kNumControls; ++j) (*Huu)(i, j) = h.v[i].v[j];
  }
  return std::isfinite(*H) && Hu->allFinite() && Huu->allFinite();
}

constexpr double kFlat = 1e-12;  // MinimiseOverControls: below this H's changes are not resolved [1]

// Damped Newton on H_u = 0 from us (a minimum of H: steps along the positive definite part of
// H_uu with a backtracking line search on H). Near the minimum, where H stops changing in floating
// point long before H_u does, a step is accepted when it reduces |H_u|: the residuals of the
// transcription are linear in the error of u*, so u* must be found to the rounding floor of H_u,
// not of H. Near means a Newton step below 1e-6, or, where H is nearly flat in a control, a step
// whose decrease of H by the quadratic model, -H_u.step / 2, is below kFlat (1 + |H|) and whose
// trial does not raise H by more than that: on the TT course a step of 1.1e-6 of the yaw
// acceleration (scaled) would have lowered H = 0.168 by ~6e-17, two units in its last place, and
// the line search, finding no decrease, left u* that far off and the interval's residual at
// 3.3e-6 (docs/lap_log.md "Session 52"). Converged when the Newton step is below 1e-12, or below
// 1e-9 when no trial reduces |H_u| any more.
bool MinimiseOverControls(const Vehicle& v, const Scales& sc, const RoadPoint& road,
                          const BarrierWeight& w, const StateVector<double>& xs,
                          const StateVector<double>& lambda, ControlVector<double>* us) {
  double H;
  Eigen::Vector2d Hu;
  Eigen::Matrix2d Huu;
  if (!ControlDerivatives(v, sc, road, w, xs, lambda, *us, &H, &Hu, &Huu)) return false;
  for (int it = 0; it < 60; ++it) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(Huu);
    const double floor = 1e-10 * std::max(1e-300, eig.eigenvalues().cwiseAbs().maxCoeff());
    const Eigen::Vector2d lam = eig.eigenvalues().cwiseMax(floor);
    const Eigen::Vector2d step =
        -(eig.eigenvectors() * lam.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose()) * Hu;
    const double size = step.lpNorm<Eigen::Infinity>();
    if (size < 1e-12) return eig.eigenvalues().minCoeff() > 0.0;
    double alpha = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 40 && !accepted; ++ls, alpha *= 0.5) {
      const ControlVector<double> trial = {(*us)[0] + alpha * step(0), (*us)[1] + alpha * step(1)};
      double Ht;
      Eigen::Vector2d Hut;
      Eigen::Matrix2d Huut;
      if (!ControlDerivatives(v, sc, road, w, xs, lambda, trial, &Ht, &Hut, &Huut)) continue;
      const double resolution = kFlat * (1.0 + std::abs(H));
      const bool flat = -0.5 * Hu.dot(step) < resolution && Ht <= H + resolution;
      const bool near = (size < 1e-6 || flat) && Hut.norm() < Hu.norm();
      if (Ht < H + 1e-4 * alpha * Hu.dot(step) || near) {
        *us = trial;
        H = Ht;
        Hu = Hut;
        Huu = Huut;
        accepted = true;
      }
    }
    // No decrease left: at the rounding floor of H_u if the Newton step was already tiny.
    if (!accepted) return size < 1e-9 && eig.eigenvalues().minCoeff() > 0.0;
  }
  return false;
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
