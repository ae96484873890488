// HyperDual<N>: a scalar that carries its value, gradient and Hessian with respect to N variables
// (forward-mode automatic differentiation of second order), for the model's code templated on the
// scalar (lap/model/scalar.h). The solvers take the Hessians of the Lagrangian (Ipopt oracle,
// lap/solver/direct_node.cc) and of the Hamiltonian (indirect solver, lap/solver/node.cc) from it.
//
// Why not Ceres' nested Jets, Jet<Jet<double, N>, N>, which give the same numbers: a nested Jet
// stores 1 + 2N + N^2 doubles, the gradient twice and the Hessian's symmetric halves both, and
// every operation on it builds and zeroes N inner Jets; `perf` of one midpoint of the oracle
// (bench/node_bench) found 23 % of the time in the nested Jet's constructor alone. HyperDual
// stores 1 + N + N(N+1)/2 doubles (the Hessian's lower triangle, packed row by row) and its
// product costs about half the flops. No Debian package offers a compiled second-order forward
// scalar for templated code (ADOL-C, the one there, tapes and interprets the function).
//
// Only what the model uses is defined: the arithmetic with HyperDual and double operands,
// comparisons of values, sqrt, sin, cos, log. hyper_dual_test.cc checks every operation against
// nested Jets.
#pragma once

#include <cmath>
#include <utility>

#include <Eigen/Core>

#include "lap/model/scalar.h"

namespace ttz::lap {

template <int N>
struct HyperDual {
  static constexpr int kTriangle = N * (N + 1) / 2;
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Triangle = Eigen::Matrix<double, kTriangle, 1>;

  double a;    // value
  Gradient g;  // d/dz_i
  Triangle h;  // d2/dz_i dz_j for j <= i, at Index(i, j)

  HyperDual() : a(0.0), g(Gradient::Zero()), h(Triangle::Zero()) {}
  explicit HyperDual(double value) : a(value), g(Gradient::Zero()), h(Triangle::Zero()) {}
  // The variable z_i at `value`.
  HyperDual(double value, int i) : HyperDual(value) { g[i] = 1.0; }
  // Uninitialised parts, for results whose every part is assigned next.
  struct Uninitialised {};
  explicit HyperDual(Uninitialised) {}

  static constexpr int Index(int i, int j) { return i * (i + 1) / 2 + j; }  // j <= i
  // d2/dz_i dz_j for any i, j.
  double Hessian(int i, int j) const { return i >= j ? h[Index(i, j)] : h[Index(j, i)]; }

  HyperDual& operator+=(const HyperDual& y) {
    a += y.a;
    g += y.g;
    h += y.h;
    return *this;
  }
  HyperDual& operator-=(const HyperDual& y) {
    a -= y.a;
    g -= y.g;
    h -= y.h;
    return *this;
  }
  HyperDual& operator*=(const HyperDual& y) { return *this = *this * y; }
  HyperDual& operator/=(const HyperDual& y) { return *this = *this / y; }
  HyperDual& operator+=(double s) {
    a += s;
    return *this;
  }
  HyperDual& operator-=(double s) {
    a -= s;
    return *this;
  }
  HyperDual& operator*=(double s) {
    a *= s;
    g *= s;
    h *= s;
    return *this;
  }
  HyperDual& operator/=(double s) { return *this *= 1.0 / s; }
};

namespace hyper_dual_detail {

// r.h += c (p q^T + q p^T), lower triangle, row by row, each row's length a compile-time constant.
template <int N, int... I>
inline void AddSymmetricOuterRows(double c, const typename HyperDual<N>::Gradient& p,
                                  const typename HyperDual<N>::Gradient& q, HyperDual<N>* r,
                                  std::integer_sequence<int, I...>) {
  ((r->h.template segment<I + 1>(HyperDual<N>::Index(I, 0)) +=
    (c * p[I]) * q.template head<I + 1>() + (c * q[I]) * p.template head<I + 1>()),
   ...);
}
template <int N>
inline void AddSymmetricOuter(double c, const typename HyperDual<N>::Gradient& p,
                              const typename HyperDual<N>::Gradient& q, HyperDual<N>* r) {
  AddSymmetricOuterRows<N>(c, p, q, r, std::make_integer_sequence<int, N>{});
}

// f(x) from f, f' and f'' at x.a (the chain rule of second order).
template <int N>
inline HyperDual<N> Chain(const HyperDual<N>& x, double f, double d1, double d2) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = f;
  r.g = d1 * x.g;
  r.h = d1 * x.h;
  AddSymmetricOuter<N>(0.5 * d2, x.g, x.g, &r);
  return r;
}

}  // namespace hyper_dual_detail

template <int N>
inline HyperDual<N> operator-(const HyperDual<N>& x) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = -x.a;
  r.g = -x.g;
  r.h = -x.h;
  return r;
}
// The operators build their result in one pass over their operands: taking an operand by value and
// returning `x += y` copied its 136 doubles (N = 15) twice, and those copies were 10 % of the
// indirect solver's time (perf, docs/lap_log.md "One pass per operator").
template <int N>
inline HyperDual<N> operator+(const HyperDual<N>& x, const HyperDual<N>& y) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = x.a + y.a;
  r.g = x.g + y.g;
  r.h = x.h + y.h;
  return r;
}
template <int N>
inline HyperDual<N> operator-(const HyperDual<N>& x, const HyperDual<N>& y) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = x.a - y.a;
  r.g = x.g - y.g;
  r.h = x.h - y.h;
  return r;
}
template <int N>
inline HyperDual<N> operator*(const HyperDual<N>& x, const HyperDual<N>& y) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = x.a * y.a;
  r.g = x.a * y.g + y.a * x.g;
  r.h = x.a * y.h + y.a * x.h;
  hyper_dual_detail::AddSymmetricOuter<N>(1.0, x.g, y.g, &r);
  return r;
}
// q = x / y from x = q y: q'' = (x'' - q y'' - (q' y'^T + y' q'^T)) / y.
template <int N>
inline HyperDual<N> operator/(const HyperDual<N>& x, const HyperDual<N>& y) {
  HyperDual<N> q{typename HyperDual<N>::Uninitialised{}};
  const double inv = 1.0 / y.a;
  q.a = x.a * inv;
  q.g = (x.g - q.a * y.g) * inv;
  q.h = (x.h - q.a * y.h) * inv;
  hyper_dual_detail::AddSymmetricOuter<N>(-inv, q.g, y.g, &q);
  return q;
}

template <int N>
inline HyperDual<N> operator+(const HyperDual<N>& x, double s) {
  HyperDual<N> r = x;
  r.a += s;
  return r;
}
template <int N>
inline HyperDual<N> operator+(double s, const HyperDual<N>& x) {
  return x + s;
}
template <int N>
inline HyperDual<N> operator-(const HyperDual<N>& x, double s) {
  HyperDual<N> r = x;
  r.a -= s;
  return r;
}
template <int N>
inline HyperDual<N> operator-(double s, const HyperDual<N>& x) {
  HyperDual<N> r = -x;
  r.a += s;
  return r;
}
template <int N>
inline HyperDual<N> operator*(const HyperDual<N>& x, double s) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialised{}};
  r.a = x.a * s;
  r.g = x.g * s;
  r.h = x.h * s;
  return r;
}
template <int N>
inline HyperDual<N> operator*(double s, const HyperDual<N>& x) {
  return x * s;
}
template <int N>
inline HyperDual<N> operator/(const HyperDual<N>& x, double s) {
  return x * (1.0 / s);
}
template <int N>
inline HyperDual<N> operator/(double s, const HyperDual<N>& x) {
  const double inv = 1.0 / x.a;  // s / x: f' = -s / x^2, f'' = 2 s / x^3
  return hyper_dual_detail::Chain(x, s * inv, -s * inv * inv, 2.0 * s * inv * inv * inv);
}

// Comparisons compare values (as Ceres' Jets do).
#define TTZ_HYPER_DUAL_COMPARISON(OP)                                               \
  template <int N>                                                                  \
  inline bool operator OP(const HyperDual<N>& x, const HyperDual<N>& y) {           \
    return x.a OP y.a;                                                              \
  }                                                                                 \
  template <int N>                                                                  \
  inline bool operator OP(const HyperDual<N>& x, double s) {                        \
    return x.a OP s;                                                                \
  }                                                                                 \
  template <int N>                                                                  \
  inline bool operator OP(double s, const HyperDual<N>& x) {                        \
    return s OP x.a;                                                                \
  }
TTZ_HYPER_DUAL_COMPARISON(<)
TTZ_HYPER_DUAL_COMPARISON(<=)
TTZ_HYPER_DUAL_COMPARISON(>)
TTZ_HYPER_DUAL_COMPARISON(>=)
TTZ_HYPER_DUAL_COMPARISON(==)
TTZ_HYPER_DUAL_COMPARISON(!=)
#undef TTZ_HYPER_DUAL_COMPARISON

// Found by argument-dependent lookup from the model's `using std::sqrt; sqrt(x)`.
template <int N>
inline HyperDual<N> sqrt(const HyperDual<N>& x) {
  const double r = std::sqrt(x.a);
  return hyper_dual_detail::Chain(x, r, 0.5 / r, -0.25 / (r * x.a));
}
template <int N>
inline HyperDual<N> sin(const HyperDual<N>& x) {
  const double s = std::sin(x.a);
  return hyper_dual_detail::Chain(x, s, std::cos(x.a), -s);
}
template <int N>
inline HyperDual<N> cos(const HyperDual<N>& x) {
  const double c = std::cos(x.a);
  return hyper_dual_detail::Chain(x, c, -std::sin(x.a), -c);
}
template <int N>
inline HyperDual<N> log(const HyperDual<N>& x) {
  const double inv = 1.0 / x.a;
  return hyper_dual_detail::Chain(x, std::log(x.a), inv, -inv * inv);
}

template <int N>
struct ScalarTraits<HyperDual<N>> {
  static HyperDual<N> Constant(double x) { return HyperDual<N>(x); }
  static double Value(const HyperDual<N>& x) { return x.a; }
  static HyperDual<N> Unset() { return HyperDual<N>(typename HyperDual<N>::Uninitialised{}); }
};

}  // namespace ttz::lap
