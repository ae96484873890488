// RoadTrack: road.h5 samples as smooth functions of s in the model's frame, and its input checks.
#include "lap/road_track.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

TEST(RoadTrackTest, PassesThroughTheSamplesWithKappaInTheModelsSign) {
  const RoadArtefact r = testing::SyntheticRoad(
      50.0, [](double s) { return 7.0 + 0.01 * s; }, [](double s) { return 0.02 * std::sin(0.1 * s); },
      [](double s) { return 0.001 * s; });
  const RoadTrack track(r);
  EXPECT_DOUBLE_EQ(track.Length(), 50.0);
  for (int i = 0; i <= 50; i += 7) {
    const RoadPoint p = track.At(i);
    EXPECT_NEAR(p.kappa, -r.kappa[i], 1e-12);  // model: right turn positive
    EXPECT_NEAR(p.sigma, r.sigma[i], 1e-12);
    EXPECT_NEAR(p.width, r.width[i], 1e-12);
  }
  // Between samples the cubic follows the smooth profile and its derivative.
  const RoadPoint mid = track.At(20.5);
  EXPECT_NEAR(mid.kappa, -0.02 * std::sin(2.05), 1e-5);
  EXPECT_NEAR(mid.dkappa, -0.002 * std::cos(2.05), 1e-5);
  EXPECT_NEAR(mid.sigma, 0.0205, 1e-9);  // a linear slope is reproduced exactly
}

TEST(RoadTrackTest, RejectsANonUniformOrTooShortRoad) {
  RoadArtefact r = testing::StraightRoad(10.0);
  r.s[5] += 0.3;
  try {
    RoadTrack track(r, "bent.h5");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bent.h5: dataset 's' is not uniformly spaced at sample 5"),
              std::string::npos)
        << e.what();
  }
  RoadArtefact one = testing::StraightRoad(0.0);
  EXPECT_THROW(RoadTrack(one, "one.h5"), InputError);
}

}  // namespace
}  // namespace ttz::lap
