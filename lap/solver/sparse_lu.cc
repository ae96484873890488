#include "lap/solver/sparse_lu.h"

#include <algorithm>
#include <vector>

#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

namespace ttz::lap {
namespace {

// J itself: block-banded in the unknowns' node order (interval k's residuals touch nodes k and
// k + 1), so an LU in that natural order keeps its fill inside the band. Measured on the whole
// course's 20 m mesh (161,252 unknowns, docs/lap.md): Eigen's SparseLU in natural order factorises
// in 0.24 s and solves in 0.013 s, UMFPACK (its default ordering) in 0.93 s and 0.17 s.
//
// Eigen's SparseLU reserves, before it factorises, `fillfactor` (20) times nnz(J) for each of the
// factors' values and indices: on the whole course 3.4 GB of address space, of which the factors
// use a small part (nnz(L) + nnz(U) = 1.27 nnz(J) on a 3 km window), freed after every solve.
// That free block lifted the heap's free top above malloc's trim threshold (2 GB, the most
// mallopt takes: common/memory.h), so the heap was given back to the system after every
// factorisation and every large block of the next Newton iteration was faulted in again (docs/lap.md
// "The LU's reservation"). Three times nnz(J) leaves room; SparseLU grows its arrays when the
// factors need more.
class BandedLU : public Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::NaturalOrdering<int>> {
 public:
  BandedLU() { m_perfv.fillfactor = 3; }
};
// The bordered matrix, whose dense last row and column need a fill-reducing ordering: UMFPACK
// (on the 300 m bend road of oracle_test a 5-iteration corrector on it took 0.49 s with UMFPACK,
// 1.18 s with Eigen's SparseLU and 4.0 s with KLU; SparseLU in natural order ran out of 24 GB on
// the whole course's bordered matrix).
using BorderedLU = Eigen::UmfPackLU<Eigen::SparseMatrix<double>>;

// Solves A x = b by the LU `Lu`; false when A is singular or x is not finite.
template <typename Lu>
bool SolveBy(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  Lu lu;
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

// Block elimination with the LU of J (sparse_lu.h); true when it solves the bordered system to
// 1e-9 of max(1, |b|).
bool SolveByBlockElimination(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& c,
                             const Eigen::VectorXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  const Eigen::Index n = J.rows();
  BandedLU lu;
  lu.compute(J);
  if (lu.info() != Eigen::Success) return false;
  const Eigen::VectorXd y = lu.solve(b.head(n)), z = lu.solve(c);
  x->resize(n + 1);
  (*x)[n] = (b[n] - a.head(n).dot(y)) / (a[n] - a.head(n).dot(z));
  x->head(n) = y - z * (*x)[n];
  if (!x->allFinite()) return false;
  Eigen::VectorXd miss(n + 1);
  miss.head(n) = J * x->head(n) + c * (*x)[n] - b.head(n);
  miss[n] = a.dot(*x) - b[n];
  return miss.lpNorm<Eigen::Infinity>() <= 1e-9 * std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

}  // namespace

bool SolveSquare(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  return SolveBy<BandedLU>(J, b, x);
}

bool SolveBordered(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& c,
                   const Eigen::VectorXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  return SolveByBlockElimination(J, c, a, b, x) || SolveBy<BorderedLU>(Bordered(J, c, a), b, x);
}

}  // namespace ttz::lap
