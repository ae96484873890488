// The solvers' one form of parallelism: a loop over the mesh's intervals or nodes, split in
// contiguous parts, one thread each.
#pragma once

#include <algorithm>
#include <functional>
#include <vector>

namespace ttz::lap {

// Runs work(p) for every part p in [0, parts): part 0 on the calling thread, the others on worker
// threads that stay alive between calls (a thread per call cost a fresh stack each time, whose
// pages glibc hands back when the thread ends and the kernel faults in again: ~1.4 million page
// faults on the whole TT course, docs/lap_log.md "Worker threads kept"). Returns when every part is
// done; calls from several threads at once take turns (so a part must not call RunParts).
void RunParts(int parts, const std::function<void(int)>& work);

// Runs ok(k) for every k in [0, n), split in `threads` contiguous parts; a part stops at its
// first false. True if every call returned true.
template <typename F>
bool ForEachInterval(int n, int threads, F ok) {
  const int parts = std::max(1, threads);
  std::vector<char> part_ok(parts, 1);
  auto work = [&](int p) {
    for (int k = n * p / parts; k < n * (p + 1) / parts && part_ok[p]; ++k) part_ok[p] = ok(k);
  };
  if (parts == 1)
    work(0);
  else
    RunParts(parts, work);
  return std::all_of(part_ok.begin(), part_ok.end(), [](char c) { return c != 0; });
}

}  // namespace ttz::lap
