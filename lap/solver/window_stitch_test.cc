// Carrying the slow costates across the windows' junctions (window_stitch.h): three windows whose
// costates are each a constant, the later windows' larger in lambda_e and lambda_T as a free end
// would leave them.
#include "lap/solver/window_stitch.h"

#include <gtest/gtest.h>

namespace ttz::lap {
namespace {

TEST(WindowStitchTest, ChargeAndTemperatureCostatesBecomeContinuousAndTheOthersStay) {
  // windows 1 and 2 start at nodes 4 and 7, which keep the previous window's costates: nodes 0-4
  // from window 0, 5-7 from window 1, 8-9 from window 2
  const int starts[3] = {0, 4, 7};
  const double level[3] = {1.0, 5.0, 2.0};  // each window's costates, all of them
  std::vector<StateVector<double>> lambda(10);
  for (int w = 0; w < 3; ++w)
    for (int k = w == 0 ? 0 : starts[w] + 1; k <= (w == 2 ? 9 : starts[w + 1]); ++k)
      lambda[k].fill(level[w]);
  std::vector<WindowJunction> junctions;
  for (int w = 1; w < 3; ++w) {
    WindowJunction j{starts[w], {}};
    j.jump.fill(level[w] - level[w - 1]);
    junctions.push_back(j);
  }
  std::vector<StateVector<double>> carried = lambda;
  CarrySlowCostatesUpstream(junctions, &carried);
  for (int k = 0; k < 10; ++k)
    for (int i = 0; i < kNumStates; ++i) {
      const bool slow = i == kE || i == kT;
      EXPECT_DOUBLE_EQ(carried[k][i], slow ? level[2] : lambda[k][i])
          << "node " << k << " costate " << i;
    }
}

TEST(WindowStitchTest, OneWindowIsLeftAsItIs) {
  std::vector<StateVector<double>> lambda(5);
  for (int k = 0; k < 5; ++k) lambda[k].fill(0.1 * k);
  std::vector<StateVector<double>> carried = lambda;
  CarrySlowCostatesUpstream({}, &carried);
  EXPECT_EQ(carried, lambda);
}

}  // namespace
}  // namespace ttz::lap
