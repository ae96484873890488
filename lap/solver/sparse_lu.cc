#include "lap/solver/sparse_lu.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/UmfPackSupport>

namespace ttz::lap {
namespace {

// The bordered matrix, whose dense last row and column need a fill-reducing ordering: UMFPACK
// (on the 300 m bend road of oracle_test a 5-iteration corrector on it took 0.49 s with UMFPACK,
// 1.18 s with Eigen's SparseLU and 4.0 s with KLU; SparseLU in natural order ran out of 24 GB on
// the whole course's bordered matrix).
using BorderedLU = Eigen::UmfPackLU<Eigen::SparseMatrix<double>>;

// Solves A x = b by the bordered matrix's LU; false when A is singular or x is not finite.
bool SolveByBorderedLU(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                       Eigen::VectorXd* x) {
  BorderedLU lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success) return false;
  *x = lu.solve(b);
  return lu.info() == Eigen::Success && x->allFinite();
}

// [J c; a^T], assembled.
Eigen::SparseMatrix<double> Bordered(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& c,
                                     const Eigen::VectorXd& a) {
  const Eigen::Index n = J.rows();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(J.nonZeros() + 2 * n + 1);
  for (int k = 0; k < J.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(J, k); it; ++it)
      t.emplace_back(it.row(), it.col(), it.value());
  for (Eigen::Index i = 0; i < n; ++i) {
    if (c[i] != 0.0) t.emplace_back(i, n, c[i]);
    if (a[i] != 0.0) t.emplace_back(n, i, a[i]);
  }
  t.emplace_back(n, n, a[n]);
  Eigen::SparseMatrix<double> A(n + 1, n + 1);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// Block elimination with the LU of J (sparse_lu.h), refined by at most two rounds of iterative
// refinement with the same factors; true when it solves the bordered system to 1e-9 of
// max(1, |b|).
bool SolveByBlockElimination(const Eigen::SparseMatrix<double>& J, Staircase form,
                             const Eigen::VectorXd& c, const Eigen::VectorXd& a,
                             const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  const Eigen::Index n = J.rows();
  StaircaseLU lu(form);
  if (!lu.Compute(J)) return false;
  const Eigen::VectorXd z = lu.Solve(c);
  const double pivot = a[n] - a.head(n).dot(z);
  auto solve = [&](const Eigen::VectorXd& rhs) {  // [J c; a^T] x = rhs by the elimination
    const Eigen::VectorXd y = lu.Solve(rhs.head(n));
    Eigen::VectorXd out(n + 1);
    out[n] = (rhs[n] - a.head(n).dot(y)) / pivot;
    out.head(n) = y - z * out[n];
    return out;
  };
  *x = solve(b);
  const double tolerance = 1e-9 * std::max(1.0, b.lpNorm<Eigen::Infinity>());
  for (int refinement = 0;; ++refinement) {
    if (!x->allFinite()) return false;
    Eigen::VectorXd miss(n + 1);
    miss.head(n) = J * x->head(n) + c * (*x)[n] - b.head(n);
    miss[n] = a.dot(*x) - b[n];
    if (miss.lpNorm<Eigen::Infinity>() <= tolerance) return true;
    if (refinement == 2) return false;
    *x -= solve(miss);
  }
}

}  // namespace

bool SolveSquare(const Eigen::SparseMatrix<double>& J, Staircase form, const Eigen::VectorXd& b,
                 Eigen::VectorXd* x) {
  StaircaseLU lu(form);
  if (!lu.Compute(J)) return false;
  *x = lu.Solve(b);
  return x->allFinite();
}

bool NearNullVector(const Eigen::SparseMatrix<double>& J, Staircase form, int iterations,
                    Eigen::VectorXd* x, double* shrunk) {
  StaircaseLU lu(form);
  if (!lu.Compute(J)) return false;
  *x = Eigen::VectorXd::Ones(J.cols()).normalized();
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd y = lu.Solve(*x);
    const double norm = y.norm();
    if (!std::isfinite(norm) || norm == 0.0) return false;
    *x = y / norm;
  }
  *shrunk = (J * *x).norm();
  return std::isfinite(*shrunk);
}

bool SolveBordered(const Eigen::SparseMatrix<double>& J, Staircase form, const Eigen::VectorXd& c,
                   const Eigen::VectorXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  return SolveByBlockElimination(J, form, c, a, b, x) ||
         SolveByBorderedLU(Bordered(J, c, a), b, x);
}

}  // namespace ttz::lap
