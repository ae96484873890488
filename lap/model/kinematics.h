// Kinematics of the mono-wheel on the 3-D road: eq. 10 (tracking), eq. 11 (velocity and angular
// velocity of the frame W_m) and the time derivatives of those velocities that eq. 13-16 need.
//
// Those derivatives depend on the unknown accelerations (dV/dt, dbeta/dt, ...); they are kept as
// affine functions of the acceleration vector (Affine below), so eq. 13-16 become a linear system
// in the accelerations (the matrix A_s of eq. 36).
#pragma once

#include <array>
#include <cmath>

#include "lap/model/road_point.h"
#include "lap/model/scalar.h"
#include "lap/model/state.h"

namespace ttz::lap {

// The accelerations of eq. 13-16, the unknowns of the linear system A a = b.
enum AccelIndex : int { kVdot = 0, kBetadot, kZddot, kPhiddot, kOmegaWdot, kNumAccels };

// c + sum_j a[j] * acc_j. `used` marks the coefficients that may be non-zero: most are zero
// (dv_x is acc_0 alone), and the operators skip those, which matters with nested Jets, where a
// product costs a thousand flops (bench/node_bench). a[j] is read only where used: the others are
// zero and, for HyperDual numbers, left unset (zeroing the five coefficients of every temporary
// cost more than the arithmetic in NewtonEuler, bench/node_bench).
template <typename T>
struct Affine {
  T c;
  std::array<T, kNumAccels> a = UnsetArray<T, kNumAccels>();
  unsigned used = 0;  // bit j: a[j] may be non-zero (and is set)

  explicit Affine(const T& constant = Cst<T>(0.0)) : c(constant) {}
  static Affine Unit(int j) {
    Affine r;
    r.Set(j, Cst<T>(1.0));
    return r;
  }
  void Set(int j, const T& coefficient) {
    a[j] = coefficient;
    used |= 1u << j;
  }
  bool Uses(int j) const { return (used >> j) & 1u; }
  Affine operator+(const Affine& o) const { return Combine(o, 1.0); }
  Affine operator-(const Affine& o) const { return Combine(o, -1.0); }
  template <typename K>  // K = T or double
  Affine operator*(const K& k) const {
    Affine r(c * k);
    r.used = used;
    for (int j = 0; j < kNumAccels; ++j)
      if (Uses(j)) r.a[j] = a[j] * k;
    return r;
  }

 private:
  // *this + sign o, sign = +-1.
  Affine Combine(const Affine& o, double sign) const {
    Affine r(sign > 0.0 ? c + o.c : c - o.c);
    r.used = used | o.used;
    for (int j = 0; j < kNumAccels; ++j) {
      if (Uses(j) && o.Uses(j))
        r.a[j] = sign > 0.0 ? a[j] + o.a[j] : a[j] - o.a[j];
      else if (Uses(j))
        r.a[j] = a[j];
      else if (o.Uses(j))
        r.a[j] = sign > 0.0 ? o.a[j] : -o.a[j];
    }
    return r;
  }
};

template <typename T>
struct Kinematics {
  T sdot, ndot, alphadot;           // eq. 10a-c [m/s], [m/s], [rad/s]
  T Omega_x, Omega_y, Omega_z;      // eq. 11a [rad/s]
  T v_x, v_y, v_z;                  // eq. 11b [m/s]
  Affine<T> dv_x, dv_y, dv_z;       // time derivatives of v_x, v_y, v_z [m/s^2]
  Affine<T> dOmega_x, dOmega_y;     // time derivatives of Omega_x, Omega_y [rad/s^2]
  T dOmega_z;                       // the control dOmega_z/dt [rad/s^2] (state.h)
};

template <typename T>
Kinematics<T> ComputeKinematics(const StateVector<T>& x, const ControlVector<T>& u,
                                const RoadPoint& road) {
  using std::cos;
  using std::sin;
  const T& n = x[kN];
  const T& alpha = x[kAlpha];
  const T& V = x[kV];
  const T& beta = x[kBeta];
  const T sa = sin(alpha), ca = cos(alpha);
  Kinematics<T> k;
  const T D = 1.0 - n * road.kappa;         // 1 - n kappa
  const T c = beta * sa + ca;               // beta sin(alpha) + cos(alpha)
  k.sdot = V * c / D;                                       // eq. 10a
  k.ndot = V * sa - V * beta * ca;                          // eq. 10b
  k.Omega_z = x[kOmegaZ];
  k.dOmega_z = u[kYawAccel];
  k.alphadot = k.Omega_z - road.kappa * (V * ca + V * beta * sa) / D;  // eq. 10c
  const T P = road.nu * sa + road.tau * ca;
  const T Q = road.nu * ca - road.tau * sa;
  k.Omega_x = k.sdot * P;                                   // eq. 11a
  k.Omega_y = k.sdot * Q;
  k.v_x = V;                                                // eq. 11b
  k.v_y = -V * beta;
  k.v_z = k.sdot * road.tau * n;

  // d(sdot)/dt = dV/dt c/D + V (dbeta/dt sin(alpha) + (beta cos(alpha) - sin(alpha)) dalpha/dt)/D
  //              + V c (dn/dt kappa + n kappa' sdot) / D^2
  Affine<T> sddot(V * (beta * ca - sa) * k.alphadot / D +
                  V * c * (k.ndot * road.kappa + n * road.dkappa * k.sdot) / (D * D));
  sddot.Set(kVdot, c / D);
  sddot.Set(kBetadot, V * sa / D);
  const T dP = (road.dnu * sa + road.dtau * ca) * k.sdot + Q * k.alphadot;
  const T dQ = (road.dnu * ca - road.dtau * sa) * k.sdot - P * k.alphadot;
  k.dOmega_x = sddot * P + Affine<T>(k.sdot * dP);
  k.dOmega_y = sddot * Q + Affine<T>(k.sdot * dQ);
  k.dv_x = Affine<T>::Unit(kVdot);
  k.dv_y = Affine<T>::Unit(kVdot) * (-beta) + Affine<T>::Unit(kBetadot) * (-V);
  k.dv_z = sddot * (road.tau * n) +
           Affine<T>(k.sdot * (road.dtau * k.sdot * n + road.tau * k.ndot));
  return k;
}

}  // namespace ttz::lap
