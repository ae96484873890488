// The solvers' parallel loop (parallel.h): every index once, in every split, call after call on
// the same worker threads; a part stops at its first false; callers on two threads take turns.
#include "lap/solver/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace ttz::lap {
namespace {

TEST(ParallelTest, EveryIndexOnceInEverySplitCallAfterCall) {
  for (int round = 0; round < 50; ++round)
    for (int threads : {1, 2, 3, 4, 2})
      for (int n : {0, 1, 7, 1000}) {
        std::vector<std::atomic<int>> visits(n);
        ASSERT_TRUE(ForEachInterval(n, threads, [&](int k) {
          ++visits[k];
          return true;
        }));
        for (int k = 0; k < n; ++k) ASSERT_EQ(visits[k].load(), 1) << threads << " " << n << " " << k;
      }
}

TEST(ParallelTest, APartStopsAtItsFirstFalse) {
  std::vector<std::atomic<int>> visits(100);
  EXPECT_FALSE(ForEachInterval(100, 2, [&](int k) {
    ++visits[k];
    return k != 10;  // in the first half
  }));
  for (int k = 0; k < 100; ++k) EXPECT_EQ(visits[k].load(), k <= 10 || k >= 50 ? 1 : 0) << k;
}

// An exception in the calling thread's part reaches the caller once the other parts are done, and
// the workers serve the next call.
TEST(ParallelTest, AnExceptionInTheCallersPartReachesTheCaller) {
  std::atomic<int> second_half{0};
  EXPECT_THROW(ForEachInterval(100, 2,
                               [&](int k) {
                                 if (k == 0) throw std::runtime_error("part 0");
                                 second_half += k >= 50;
                                 return true;
                               }),
               std::runtime_error);
  EXPECT_EQ(second_half.load(), 50);
  EXPECT_TRUE(ForEachInterval(10, 2, [](int) { return true; }));
}

TEST(ParallelTest, CallersOnTwoThreadsTakeTurns) {
  std::atomic<long> sum{0};
  auto caller = [&] {
    for (int round = 0; round < 200; ++round)
      ForEachInterval(64, 2, [&](int k) {
        sum += k;
        return true;
      });
  };
  std::thread other(caller);
  caller();
  other.join();
  EXPECT_EQ(sum.load(), 2L * 200 * (63 * 64 / 2));
}

}  // namespace
}  // namespace ttz::lap
