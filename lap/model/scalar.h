// Scalar helpers for model code templated on T = double, ceres::Jet<double, N> (first derivatives)
// or ceres::Jet<ceres::Jet<double, N>, M> (second derivatives).
//
// Ceres 2.1 mixes a Jet<U, N> only with a scalar of type U, so for nested Jets `2.0 * x` would not
// compile. The operators below add the missing mixed arithmetic of a nested Jet with a double, so
// the physics reads as the paper's equations. Comparisons (x < 0.0) compare values already.
#pragma once

#include <ceres/jet.h>

#include <array>
#include <type_traits>
#include <utility>

namespace ceres {

#define TTZ_NESTED_JET_OP(OP)                                                                  \
  template <typename U, int N, int M>                                                         \
  inline Jet<Jet<U, N>, M> operator OP(const Jet<Jet<U, N>, M>& f, double s) {                \
    return f OP Jet<U, N>(s);                                                                 \
  }                                                                                           \
  template <typename U, int N, int M>                                                         \
  inline Jet<Jet<U, N>, M> operator OP(double s, const Jet<Jet<U, N>, M>& f) {                \
    return Jet<U, N>(s) OP f;                                                                 \
  }
TTZ_NESTED_JET_OP(+)
TTZ_NESTED_JET_OP(-)
#undef TTZ_NESTED_JET_OP

// A nested Jet times a double scales each part by the double (Ceres would promote the double to a
// Jet<U, N> and multiply Jets: twice the work, node_bench).
template <typename U, int N, int M>
inline Jet<Jet<U, N>, M> operator*(const Jet<Jet<U, N>, M>& f, double s) {
  Jet<Jet<U, N>, M> r;
  r.a = f.a * s;
  for (int i = 0; i < M; ++i) r.v[i] = f.v[i] * s;
  return r;
}
template <typename U, int N, int M>
inline Jet<Jet<U, N>, M> operator*(double s, const Jet<Jet<U, N>, M>& f) {
  return f * s;
}
template <typename U, int N, int M>
inline Jet<Jet<U, N>, M> operator/(const Jet<Jet<U, N>, M>& f, double s) {
  return f * (1.0 / s);
}
template <typename U, int N, int M>
inline Jet<Jet<U, N>, M> operator/(double s, const Jet<Jet<U, N>, M>& f) {
  return Jet<U, N>(s) / f;
}

}  // namespace ceres

namespace ttz::lap {

// Unset(): a T whose value is never read before it is assigned (zero where that costs nothing;
// HyperDual leaves its parts unset, lap/model/hyper_dual.h).
template <typename T>
struct ScalarTraits {
  static T Constant(double x) { return T(x); }
  static double Value(const T& x) { return static_cast<double>(x); }
  static T Unset() { return T(0.0); }
};

template <typename U, int N>
struct ScalarTraits<ceres::Jet<U, N>> {
  static ceres::Jet<U, N> Constant(double x) { return ceres::Jet<U, N>(ScalarTraits<U>::Constant(x)); }
  static double Value(const ceres::Jet<U, N>& x) { return ScalarTraits<U>::Value(x.a); }
  static ceres::Jet<U, N> Unset() { return ceres::Jet<U, N>(); }
};

// {make(), make(), ...}: one value per index, each built in place.
template <typename F, std::size_t... I>
std::array<std::invoke_result_t<F>, sizeof...(I)> ArrayOf(const F& make, std::index_sequence<I...>) {
  return {((void)I, make())...};
}
// n Unset() values.
template <typename T, std::size_t n>
std::array<T, n> UnsetArray() {
  return ArrayOf(ScalarTraits<T>::Unset, std::make_index_sequence<n>{});
}

// The constant x as a T (derivative parts zero).
template <typename T>
inline T Cst(double x) {
  return ScalarTraits<T>::Constant(x);
}

// The value part of x as a double (drops all derivatives).
template <typename T>
inline double Val(const T& x) {
  return ScalarTraits<T>::Value(x);
}

}  // namespace ttz::lap
