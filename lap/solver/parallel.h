// The solvers' one form of parallelism: a loop over the mesh's intervals or nodes, split in
// contiguous parts, one thread each.
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace ttz::lap {

// Runs ok(k) for every k in [0, n), split in `threads` contiguous parts; a part stops at its
// first false. True if every call returned true.
template <typename F>
bool ForEachInterval(int n, int threads, F ok) {
  const int parts = std::max(1, threads);
  std::vector<char> part_ok(parts, 1);
  auto work = [&](int p) {
    for (int k = n * p / parts; k < n * (p + 1) / parts && part_ok[p]; ++k) part_ok[p] = ok(k);
  };
  std::vector<std::thread> pool;
  for (int p = 1; p < parts; ++p) pool.emplace_back(work, p);
  work(0);
  for (std::thread& t : pool) t.join();
  return std::all_of(part_ok.begin(), part_ok.end(), [](char c) { return c != 0; });
}

}  // namespace ttz::lap
