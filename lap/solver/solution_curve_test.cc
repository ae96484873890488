// Tests of the path follower's pieces (solution_curve.h) that stand alone; FollowPath itself is
// exercised through the indirect solver (indirect_test.cc, oracle_test.cc).
#include "lap/solver/solution_curve.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace ttz::lap {
namespace {

// Correctors' max |G| sequences from the TT course's first 10 km (docs/lap.md "Stalled
// correctors").
TEST(CorrectorStalledTest, AFloorOrACycleIsStalled) {
  EXPECT_TRUE(CorrectorStalled({1.9e-1, 6.5e-2, 6.4e-2, 6.5e-2}));  // a floor
  EXPECT_TRUE(CorrectorStalled({4.9e-2, 2.1e-2, 3.2e-2, 2.1e-2}));  // a two-cycle
  EXPECT_TRUE(CorrectorStalled({3.7e2, 1.5e2, 4.0e2}));  // running away
}

TEST(CorrectorStalledTest, ConvergenceWithABlipIsNot) {
  // converged with one iterate above its predecessor
  const std::vector<double> blip{5.5e-2, 3.1e-2, 4.9e-2, 1.7e-2, 1.3e-2, 1.6e-3, 4.4e-5, 3.8e-8};
  for (size_t k = 1; k <= blip.size(); ++k)
    EXPECT_FALSE(CorrectorStalled(std::vector<double>(blip.begin(), blip.begin() + k))) << k;
  EXPECT_FALSE(CorrectorStalled({}));
  EXPECT_FALSE(CorrectorStalled({1.0, 2.0}));  // too few iterates to say
}

TEST(CorrectorStalledTest, ANonFiniteResidualIsStalled) {
  EXPECT_TRUE(CorrectorStalled({1.0, 0.5, std::numeric_limits<double>::quiet_NaN()}));
}

}  // namespace
}  // namespace ttz::lap
