// The racing line (lap/racing_line.h): its residuals against numerical differentiation, the line
// on a straight and through a bend, and the QSS lap on it (lap/qss.h).
#include "lap/racing_line.h"

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "lap/mesh.h"
#include "lap/qss.h"
#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

// Checks the automatic derivatives of `cost` at `values` (one scalar per parameter block).
void ExpectGradientsMatch(const ceres::CostFunction& cost, std::vector<double> values) {
  std::vector<double*> blocks;
  for (double& x : values) blocks.push_back(&x);
  ceres::NumericDiffOptions numeric;
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::GradientChecker checker(&cost, no_manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(blocks.data(), 1e-7, &results)) << results.error_log;
}

TEST(RacingLineTest, ResidualGradientsMatchNumericalDifferentiation) {
  ceres::AutoDiffCostFunction<PathCurvatureResidual, 1, 1, 1, 1> curvature(
      new PathCurvatureResidual{0.01, 4.0, 6.0});
  ExpectGradientsMatch(curvature, {0.3, -1.2, 2.1});
  ceres::AutoDiffCostFunction<PathCurvatureChangeResidual, 1, 1, 1, 1, 1> change(
      new PathCurvatureChangeResidual{0.01, -0.02, 4.0, 5.0, 7.0, 30.0});
  ExpectGradientsMatch(change, {0.3, -1.2, 2.1, 0.7});
}

TEST(RacingLineTest, AStraightRoadKeepsTheCentreLine) {
  const RoadTrack road(testing::StraightRoad(300.0));
  const RacingLine line = ComputeRacingLine(road, UniformMesh(road.Length(), 5.0), 0.5);
  for (size_t k = 0; k < line.n.size(); ++k) {
    EXPECT_NEAR(line.n[k], 0.0, 1e-9) << k;
    EXPECT_NEAR(line.kappa[k], 0.0, 1e-9) << k;
  }
}

// A line that starts off the centre line (a window's start, RacingLineOptions::start_offset_m)
// keeps its offset along a straight: any return to the centre line would bend the path.
TEST(RacingLineTest, AStraightRoadKeepsTheStartOffset) {
  const RoadTrack road(testing::StraightRoad(300.0));
  RacingLineOptions options;
  options.start_offset_m = 1.5;
  const RacingLine line = ComputeRacingLine(road, UniformMesh(road.Length(), 5.0), 0.5, options);
  for (size_t k = 0; k < line.n.size(); ++k) EXPECT_NEAR(line.n[k], 1.5, 1e-6) << k;
}

// A 20 m bend of 90 degrees (radius 40 m, road.h5's left turn) between straights, on a 10 m wide
// road: the line enters wide, cuts to the inside at the apex and leaves wide, within the usable
// half width (0.9 x (5 - 0.5) m), and bends less sharply than the road.
class RacingLineBendTest : public ::testing::Test {
 protected:
  static double Kappa(double s) {
    const double start = 150.0, length = 0.5 * M_PI * 40.0;
    return s >= start && s <= start + length ? 1.0 / 40.0 : 0.0;
  }
  RoadTrack road{testing::SyntheticRoad(350.0, 10.0, Kappa, testing::Zero)};
  std::vector<double> mesh = UniformMesh(road.Length(), 2.0);
  RacingLine line = ComputeRacingLine(road, mesh, 0.5);
};

TEST_F(RacingLineBendTest, TheLineCutsTheBendWithinTheBorders) {
  const double bound = 0.9 * 4.5;
  double widest = 0.0, sharpest = 0.0, line_squares = 0.0, road_squares = 0.0;
  for (size_t k = 0; k < mesh.size(); ++k) {
    EXPECT_LE(std::abs(line.n[k]), bound + 1e-9) << mesh[k];
    widest = std::max(widest, std::abs(line.n[k]));
    sharpest = std::max(sharpest, std::abs(line.kappa[k]));
    line_squares += line.kappa[k] * line.kappa[k];
    road_squares += std::pow(road.At(mesh[k]).kappa, 2);
  }
  EXPECT_GT(widest, 0.9 * bound);  // it uses the road
  EXPECT_LT(sharpest, 0.9 / 40.0);
  EXPECT_LT(line_squares, 0.8 * road_squares) << line_squares / road_squares;  // measured 0.73
  // The model's n is right positive, so the inside of a left turn is n < 0 at the apex; the
  // bend is approached from the outside.
  const auto at = [&](double s) {
    return line.n[std::lower_bound(mesh.begin(), mesh.end(), s) - mesh.begin()];
  };
  EXPECT_LT(at(150.0 + 0.25 * M_PI * 40.0), -0.5 * bound);
  EXPECT_GT(at(120.0), 0.0);
  EXPECT_EQ(line.n.front(), 0.0);
}

// The QSS on the line carries more speed through the bend than the centre line's (the guess the
// solvers start from; the centre line's stays the yardstick), and its states hold the line.
TEST_F(RacingLineBendTest, TheQssOnTheLineIsFasterAndHoldsTheLine) {
  const Vehicle v = testing::Bx15();
  const QssLap centre = ComputeQss(v, road, mesh);
  const QssLap on_line = ComputeQss(v, road, mesh, line);
  EXPECT_LT(on_line.lap_time, centre.lap_time - 0.2);
  for (size_t k = 1; k < mesh.size(); ++k) {
    EXPECT_EQ(on_line.x[k][kN], line.n[k]);
    // alpha + beta = atan(n' / (1 - n kappa)) (eq. 10), with the QSS's small sideslip beta.
    EXPECT_NEAR(std::tan(on_line.x[k][kAlpha] + on_line.x[k][kBeta]) *
                    (1.0 - line.n[k] * road.At(mesh[k]).kappa),
                line.dn_ds[k], 0.05)
        << mesh[k];
  }
}

}  // namespace
}  // namespace ttz::lap
