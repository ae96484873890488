// The LU of the indirect solver's J (lap/solver/staircase_lu.h) against the general sparse LU it
// replaced (Eigen's SparseLU in J's natural order): seconds of one factorisation and of one solve,
// each the least of three, on a random matrix of J's staircase form (CurveSystem::kJacobianForm:
// blocks of 26 rows, the first column group of 13) with N row blocks, as many as the TT course's
// intervals on the 20 m mesh with at most 0.5 s (6,202: docs/lap_log.md "The staircase LU"). Random
// entries in [-1, 1], 4 added on the diagonal; the two solutions' largest difference is printed
// as a check.
//
//   lu_bench [N]
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "common/memory.h"
#include "lap/solver/solution_curve.h"
#include "lap/solver/staircase_lu.h"
#include "lap/testing/random_staircase.h"

namespace {

double Seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

int main(int argc, char** argv) {
  ttz::KeepFreedMemory();  // as lap and lap_bench do
  constexpr ttz::lap::Staircase form = ttz::lap::CurveSystem::kJacobianForm;
  const int N = argc > 1 ? std::atoi(argv[1]) : 6202;
  const Eigen::SparseMatrix<double> J =
      ttz::lap::testing::RandomStaircase(form.block_rows, form.first_width, N, 1, 4.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(J.rows(), -1.0, 1.0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double stair[2] = {kInf, kInf}, sparse[2] = {kInf, kInf}, diff = 0.0;
  for (int rep = 0; rep < 3; ++rep) {
    auto t0 = std::chrono::steady_clock::now();
    ttz::lap::StaircaseLU lu(form);
    if (!lu.Compute(J)) return 1;
    auto t1 = std::chrono::steady_clock::now();
    const Eigen::VectorXd x = lu.Solve(b);
    auto t2 = std::chrono::steady_clock::now();
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::NaturalOrdering<int>> slu;
    slu.compute(J);
    auto t3 = std::chrono::steady_clock::now();
    const Eigen::VectorXd y = slu.solve(b);
    auto t4 = std::chrono::steady_clock::now();
    stair[0] = std::min(stair[0], Seconds(t0, t1));
    stair[1] = std::min(stair[1], Seconds(t1, t2));
    sparse[0] = std::min(sparse[0], Seconds(t2, t3));
    sparse[1] = std::min(sparse[1], Seconds(t3, t4));
    diff = (x - y).lpNorm<Eigen::Infinity>();
  }
  std::printf("%d unknowns: staircase LU %.4f s + %.4f s per solve; Eigen SparseLU (natural order) "
              "%.4f s + %.4f s; solutions differ by %.1e\n",
              static_cast<int>(J.rows()), stair[0], stair[1], sparse[0], sparse[1], diff);
  return 0;
}
