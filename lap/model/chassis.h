// Newton-Euler equations of the mono-wheel (eq. 13a-c, 14 with T_phi of eq. 15, and 16), written
// as in the paper with every term moved to the left: each equation is an affine function of the
// accelerations a = (dV/dt, dbeta/dt, d2z/dt2, d2phi/dt2, domega_w/dt), so together they are the
// linear system A a = b (the mechanical rows of A_s in eq. 36), solved by SolveAccelerations.
//
// Decisions (see docs/lap.md): the paper's small-slope approximation sigma ~ sin(sigma) is replaced
// by sin(sigma) (road.h5 defines dz/ds = sin(sigma)), cos(sigma) ~ 1 is kept as in the paper;
// the dOmega_z/dt terms of eq. 13a and 16 are kept (Omega_z is a state, lap/model/state.h).
// Banking xi (eq. 2; the paper's xi = 0) tilts gravity in the road frame: g sin(xi) to the right
// (the model's +y) and g cos(xi) along the road's normal, cos(sigma) ~ 1 kept on both. In the
// vehicle's frame, turned by alpha from the road's, gravity's forward component is
// -g sin(sigma) cos(alpha) + g sin(xi) sin(alpha) and its lateral g sin(sigma) sin(alpha) +
// g sin(xi) cos(alpha): where the paper has g sigma cos(alpha), g sigma sin(alpha) and g.
#pragma once

#include <array>
#include <cmath>

#include "lap/model/kinematics.h"
#include "lap/model/tyre.h"
#include "lap/model/vehicle.h"

namespace ttz::lap {

// External loads acting on the chassis.
template <typename T>
struct ChassisLoads {
  T F_x, F_y, N;   // tyre forces [N]
  T D, L;          // aerodynamic drag and lift [N]
  T tau_w, tau_r;  // wheel torque and rolling resistance [N m]
};

template <typename T>
using Equations = std::array<Affine<T>, kNumAccels>;

// Eq. 13a-c, 14-15 and 16 as residuals (left minus right side) affine in the accelerations.
template <typename T>
Equations<T> NewtonEuler(const Vehicle& v, const StateVector<T>& x, const Kinematics<T>& k,
                         const ChassisLoads<T>& f, const RoadPoint& road) {
  using std::cos;
  using std::sin;
  using A = Affine<T>;
  const double M = v.M, a = v.h - v.r_t, r_t = v.r_t, g = v.g;
  const double gs = g * std::sin(road.sigma);  // g sigma of the paper
  const double gb = g * std::sin(road.xi);     // gravity across the banked road, to the right
  const double gn = g * std::cos(road.xi);     // gravity along the road's normal (g in the paper)
  const T& z = x[kZ];
  const T& phi = x[kPhi];
  const T& phid = x[kOmegaPhi];
  const T& zd = x[kZdot];
  const T sp = sin(phi), cp = cos(phi);
  const T sal = sin(x[kAlpha]), cal = cos(x[kAlpha]);
  const T g_x = gs * cal - gb * sal;  // minus gravity's forward component in the vehicle frame
  const T g_y = gs * sal + gb * cal;  // gravity's lateral component in the vehicle frame
  const T &Ox = k.Omega_x, &Oy = k.Omega_y, &Oz = k.Omega_z;
  const T &vx = k.v_x, &vy = k.v_y, &vz = k.v_z;
  const A zdd = A::Unit(kZddot), phidd = A::Unit(kPhiddot), wd = A::Unit(kOmegaWdot);
  Equations<T> e;

  // eq. 13a
  e[0] = k.dv_x * M + k.dOmega_y * ((cp * (-a) - r_t + z) * M) +
         A(-2.0 * M * a * (Oz * cp - Oy * sp) * phid - M * sp * a * k.dOmega_z + 2.0 * M * Oy * zd -
           M * Ox * Oz * a * cp + M * Ox * Oy * a * sp + M * ((z - r_t) * Ox + vy) * Oz +
           M * Oy * vz - (f.F_x - f.D - M * g_x));
  // eq. 13b
  e[1] = k.dv_y * M + phidd * (M * cp * a) + k.dOmega_x * (M * (a * cp + r_t - z)) +
         A(-M * sp * a * phid * phid - 2.0 * M * sp * Ox * a * phid - 2.0 * M * Ox * zd -
           M * a * (Oz * Oz + Ox * Ox) * sp - M * Oy * Oz * a * cp - M * ((r_t - z) * Oy - vx) * Oz -
           M * Ox * vz - (f.F_y + f.L * sp + M * g_y));
  // eq. 13c
  e[2] = zdd * M + phidd * (M * sp * a) + k.dOmega_x * (M * sp * a) + k.dv_z * M +
         A(M * cp * a * phid * phid + 2.0 * M * cp * Ox * a * phid +
           M * cp * a * (Ox * Ox + Oy * Oy) + M * Oy * Oz * a * sp - M * (z - r_t) * Ox * Ox +
           M * Ox * vy - M * (z - r_t) * Oy * Oy - M * Oy * vx - (M * gn - f.N - f.L * cp));
  // eq. 15: T_phi
  const A T_phi =
      (zdd + k.dv_z + A(-Oy * vx + Ox * vy - gn)) * (a * sp) -
      (k.dv_y + A(-2.0 * Ox * zd + Ox * vz - Oz * vx + g_y)) * (a * cp) +
      (k.dOmega_x * (2.0 * cp) + A(-2.0 * cp * Oz * Oy + sp * (Oy * Oy - Oz * Oz - phid * phid -
                                                              2.0 * Ox * phid))) *
          (a * (r_t - z)) +
      (k.dOmega_x + A(sp * cp * (Oy * Oy - Oz * Oz) - 2.0 * cp * cp * Ox * Oy)) * (a * a) +
      k.dOmega_x * (z * z - 2.0 * r_t * z) + A((v.h - z) * (v.h - 2.0 * r_t + z) * Oy * Oz) +
      (k.dv_y + A(-vz * Ox + vx * Oz - 2.0 * zd * Ox - g_y)) * (r_t - z);
  // eq. 14
  e[3] = phidd * ((-a * (z - r_t) * cp + a * a) * M + v.I_xx) + k.dOmega_x * v.I_xx +
         A((Oz * cp - Oy * sp) * v.I_gy * x[kOmegaW] + sp * (z - r_t) * f.L +
           (v.I_yy - v.I_zz) * (cp * sp * (Oy * Oy - Oz * Oz) + Oy * Oz * (1.0 - 2.0 * cp * cp))) +
         T_phi * M;
  // eq. 16
  e[4] = wd * v.I_wy - k.dOmega_y * (v.I_wy * cp) +
         A(-f.tau_w + f.tau_r + f.F_x * (v.r - v.r_t * (1.0 - cp) - z * cp) -
           v.I_wy * (sp * k.dOmega_z + (Oz * cp - Oy * sp) * phid));
  return e;
}

// Solves the affine equations e(a) = 0 for the accelerations a: Gaussian elimination with partial
// pivoting on the values (Eigen's LU does not accept nested Jets), skipping the coefficients that
// are structurally zero (Affine::used), which are never read (nor, for HyperDual, set).
template <typename T>
std::array<T, kNumAccels> SolveAccelerations(const Equations<T>& e) {
  constexpr int n = kNumAccels;
  using Row = std::array<T, n + 1>;  // [A | b]
  std::array<Row, n> m = ArrayOf([] { return UnsetArray<T, n + 1>(); }, std::make_index_sequence<n>{});
  std::array<unsigned, n> nz;  // bit j of nz[i]: m[i][j] may be non-zero (and is set)
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      if (e[i].Uses(j)) m[i][j] = e[i].a[j];
    m[i][n] = -e[i].c;
    nz[i] = e[i].used | (1u << n);
  }
  auto may_be_non_zero = [&](int i, int j) { return (nz[i] >> j) & 1u; };
  auto value = [&](int i, int j) { return may_be_non_zero(i, j) ? std::abs(Val(m[i][j])) : 0.0; };
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int i = col + 1; i < n; ++i)
      if (value(i, col) > value(pivot, col)) pivot = i;
    std::swap(m[col], m[pivot]);
    std::swap(nz[col], nz[pivot]);
    for (int i = col + 1; i < n; ++i) {
      if (!may_be_non_zero(i, col)) continue;
      const T factor = m[i][col] / m[col][col];
      for (int j = col + 1; j <= n; ++j) {
        if (!may_be_non_zero(col, j)) continue;
        m[i][j] = may_be_non_zero(i, j) ? m[i][j] - factor * m[col][j] : -(factor * m[col][j]);
      }
      nz[i] |= nz[col];
    }
  }
  std::array<T, n> acc;
  for (int i = n - 1; i >= 0; --i) {
    T sum = m[i][n];
    for (int j = i + 1; j < n; ++j)
      if (may_be_non_zero(i, j)) sum = sum - m[i][j] * acc[j];
    acc[i] = sum / m[i][i];
  }
  return acc;
}

}  // namespace ttz::lap
