// Random matrices in the staircase form of lap/solver/staircase_lu.h, for its test and for
// bench/lu_bench.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/SparseCore>

namespace ttz::lap::testing {

// A matrix in staircase form (R, g) with N row blocks: every entry of the staircase drawn from
// [-1, 1] by a generator seeded with `seed`, `diagonal` added on the diagonal (0: no diagonal
// dominance, the elimination has to pivot).
inline Eigen::SparseMatrix<double> RandomStaircase(int R, int g, int N, unsigned seed,
                                                   double diagonal = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < N; ++k) {
    const int first = k == 0 ? 0 : g + R * (k - 1);     // group k's first column
    const int last = std::min(g + R * (k + 1), N * R);  // past group k + 1's
    for (int r = 0; r < R; ++r)
      for (int c = first; c < last; ++c)
        t.emplace_back(k * R + r, c, u(rng) + (k * R + r == c ? diagonal : 0.0));
  }
  Eigen::SparseMatrix<double> J(N * R, N * R);
  J.setFromTriplets(t.begin(), t.end());
  return J;
}

}  // namespace ttz::lap::testing
