// The sparse linear solves of the indirect solver's arclength continuation (indirect.cc): a square
// system J x = b, and J bordered by one row and one column, by LU (not the normal equations: J's
// condition is not squared). J is in staircase form, as the transcription's is in the order of
// the nodes: its LU (staircase_lu.h) keeps that order; the bordered matrix's (UMFPACK,
// SuiteSparse) orders for fill.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "lap/solver/staircase_lu.h"

namespace ttz::lap {

// Solves J x = b for J in the staircase `form`; false when J is singular, not in that form or x
// is not finite.
bool SolveSquare(const Eigen::SparseMatrix<double>& J, Staircase form, const Eigen::VectorXd& b,
                 Eigen::VectorXd* x);

// A unit vector x that J in staircase `form` maps to nearly zero, by `iterations` steps of
// inverse iteration (x <- J^-1 x / |J^-1 x| from a vector of ones, one LU of J), and |J x| in
// `shrunk`: an upper bound on J's smallest singular value, and its smallest |eigenvalue| once the
// iteration has converged to a real one. False when J is singular or the iterates are not
// finite. Where the continuation stops it says where on the road (indirect.cc,
// NearSingularDirection; docs/lap_log.md "Session 52").
bool NearNullVector(const Eigen::SparseMatrix<double>& J, Staircase form, int iterations,
                    Eigen::VectorXd* x, double* shrunk);
inline constexpr int kNearNullIterations = 10;  // the steps NearNullVector takes in lap and stall_bench

// Solves the bordered system [J c; a^T] x = b (J n x n, c and b of size n and n + 1, a of size
// n + 1) by block elimination with the staircase LU of J alone (Keller's bordering
// algorithm): J y = b_J, J z = c, x_n = (b_n - a_J.y) / (a_n - a_J.z), x_J = y - z x_n. Where J is
// singular or nearly so (at a turning point of the continuation's curve, which the bordered matrix
// is built to pass) that is inaccurate: while the bordered matrix times x misses b by more than
// 1e-9 of max(1, |b|) (max norms), x is refined by the same elimination of the miss (at most
// twice), and if it still misses, the LU of the bordered matrix itself solves it, whose dense last
// row and column fill the factors (on the whole TT course one such solve took ~15 s and 2.8 GB:
// docs/lap_log.md "The node evaluations built for this processor"). False when neither gives a finite
// x.
bool SolveBordered(const Eigen::SparseMatrix<double>& J, Staircase form, const Eigen::VectorXd& c,
                   const Eigen::VectorXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x);

}  // namespace ttz::lap
