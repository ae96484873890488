// The sparse solves of the arclength continuation (sparse_lu.h) against dense LU: the bordered
// system by block elimination where J is regular, by block elimination and a round of refinement
// where J is nearly singular (J(17, 17) = 1e-13: a first miss of 3.5e-4, then 2e-16), and by the
// bordered matrix's own LU where J is singular (a turning point of the curve).
#include "lap/solver/sparse_lu.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

namespace ttz::lap {
namespace {

constexpr int kN = 60;
constexpr Staircase kForm{6, 3};  // row block k (6 rows) touches columns 6k - 3 .. 6k + 8

// A banded, diagonally dominant J (like the transcription's, regular; bandwidth 3, so in the
// staircase form kForm) with a random border and right-hand side (seeded).
struct Bordered {
  Eigen::SparseMatrix<double> J{kN, kN};
  Eigen::VectorXd c{kN}, a{kN + 1}, b{kN + 1};
  Bordered() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < kN; ++i)
      for (int j = std::max(0, i - 3); j < std::min(kN, i + 4); ++j)
        t.emplace_back(i, j, i == j ? 8.0 + u(rng) : u(rng));
    J.setFromTriplets(t.begin(), t.end());
    for (int i = 0; i < kN; ++i) c[i] = u(rng);
    for (int i = 0; i <= kN; ++i) a[i] = u(rng);
    for (int i = 0; i <= kN; ++i) b[i] = u(rng);
  }
  // The dense bordered matrix [J c; a^T].
  Eigen::MatrixXd Dense() const {
    Eigen::MatrixXd A(kN + 1, kN + 1);
    A.topLeftCorner(kN, kN) = Eigen::MatrixXd(J);
    A.topRightCorner(kN, 1) = c;
    A.bottomRows(1) = a.transpose();
    return A;
  }
  // Makes row and column k of J zero but for J(k, k) = d, and the border e_k: with d = 0 J is
  // singular while the bordered matrix is not.
  void Pinch(int k, double d) {
    for (int i = 0; i < kN; ++i) {
      if (J.coeff(i, k) != 0.0) J.coeffRef(i, k) = 0.0;
      if (J.coeff(k, i) != 0.0) J.coeffRef(k, i) = 0.0;
    }
    J.coeffRef(k, k) = d;
    c.setZero();
    c[k] = 1.0;
    a[k] = 1.0;
  }
};

void ExpectSolves(const Bordered& p) {
  Eigen::VectorXd x;
  ASSERT_TRUE(SolveBordered(p.J, kForm, p.c, p.a, p.b, &x));
  const Eigen::VectorXd dense = p.Dense().fullPivLu().solve(p.b);
  EXPECT_LE((x - dense).lpNorm<Eigen::Infinity>(), 1e-9 * dense.lpNorm<Eigen::Infinity>());
  EXPECT_LE((p.Dense() * x - p.b).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(SparseLuTest, BorderedSystemWithARegularJ) { ExpectSolves(Bordered{}); }

TEST(SparseLuTest, BorderedSystemWithASingularJ) {
  Bordered p;
  p.Pinch(17, 0.0);
  Eigen::VectorXd x;
  EXPECT_FALSE(SolveSquare(p.J, kForm, p.b.head(kN), &x));  // J alone cannot be solved
  ExpectSolves(p);
}

TEST(SparseLuTest, BorderedSystemWithANearlySingularJ) {
  Bordered p;
  p.Pinch(17, 1e-13);
  ExpectSolves(p);
}

TEST(SparseLuTest, SquareSystemAgainstDenseLu) {
  const Bordered p;
  Eigen::VectorXd x;
  ASSERT_TRUE(SolveSquare(p.J, kForm, p.b.head(kN), &x));
  const Eigen::VectorXd dense = Eigen::MatrixXd(p.J).partialPivLu().solve(p.b.head(kN));
  EXPECT_LE((x - dense).lpNorm<Eigen::Infinity>(), 1e-12);
}

// Pinched, J has the eigenvalue 1e-6 with the eigenvector e_17, its others at least 1 away from
// zero (Gershgorin: diagonals 7-9, six off-diagonals of at most 1): inverse iteration finds e_17.
TEST(SparseLuTest, NearNullVectorOfAPinchedJ) {
  Bordered p;
  p.Pinch(17, 1e-6);
  double shrunk = 0.0;
  Eigen::VectorXd x;
  ASSERT_TRUE(NearNullVector(p.J, kForm, 4, &x, &shrunk));
  EXPECT_NEAR(shrunk, 1e-6, 1e-15);
  EXPECT_NEAR(std::abs(x[17]), 1.0, 1e-12);
  p.Pinch(17, 0.0);
  EXPECT_FALSE(NearNullVector(p.J, kForm, 4, &x, &shrunk));
}

}  // namespace
}  // namespace ttz::lap
