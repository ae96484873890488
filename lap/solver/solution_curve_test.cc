// Tests of the path follower's pieces (solution_curve.h) that stand alone; FollowPath itself is
// exercised through the indirect solver (indirect_test.cc, oracle_test.cc). The square system's
// F and J, assembled in place, against Ceres' Problem::Evaluate of the same transcription.
#include "lap/solver/solution_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <ceres/ceres.h>

#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

// Correctors' max |G| sequences from the TT course's first 10 km (docs/lap_log.md "Stalled
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

TEST(CorrectorDivergedTest, AboveAMillionTimesItsStart) {
  EXPECT_TRUE(CorrectorDiverged({4.1e-2, 3.0e2, 8.2e9}, 1e-7));  // as the whole course's, to 8.2e9
  EXPECT_FALSE(CorrectorDiverged({4.1e-2, 3.0e2, 8.2e3}, 1e-7));
  EXPECT_FALSE(CorrectorDiverged({1e-9, 1e-4}, 1e-7));  // a start below the tolerance
  EXPECT_TRUE(CorrectorDiverged({1e-9, 1.0}, 1e-7));
  EXPECT_TRUE(CorrectorDiverged({1.0, std::numeric_limits<double>::infinity()}, 1e-7));
  EXPECT_FALSE(CorrectorDiverged({}, 1e-7));
}

// Step lengths |dz| of the whole TT course's barrier continuation (solution_curve.h).
TEST(CorrectorNotContractingTest, StepsThatStopShrinkingDoNotContract) {
  const std::vector<double> failed{0.85, 0.46, 0.67, 0.92, 1.0, 1.0, 1.4, 1.6};
  const std::vector<double> converged{0.18, 0.0076, 0.0014, 5.3e-5};
  for (size_t k = 1; k <= converged.size(); ++k)
    EXPECT_FALSE(CorrectorNotContracting(std::vector<double>(converged.begin(), converged.begin() + k), 0.7)) << k;
  EXPECT_FALSE(CorrectorNotContracting({failed[0], failed[1]}, 0.7));  // 0.54: still shrinking
  EXPECT_TRUE(CorrectorNotContracting({failed[0], failed[1], failed[2]}, 0.7));
  EXPECT_TRUE(CorrectorNotContracting({1.4, 0.19, 0.24}, 1.0));  // grew
  EXPECT_FALSE(CorrectorNotContracting({1.4, 0.19, 0.24}, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(CorrectorNotContracting({0.0, 0.0}, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(CorrectorNotContracting({5.0}, 0.1));  // one step: nothing to compare
}

TEST(CorrectorStalledTest, ANonFiniteResidualIsStalled) {
  EXPECT_TRUE(CorrectorStalled({1.0, 0.5, std::numeric_limits<double>::quiet_NaN()}));
}

// 80 m on a 4 m mesh, a bend on a climb, at eps 0.05 from the QSS states with costates that vary
// along the road, on two threads: F and J equal Ceres' (same rows, columns and entries).
TEST(CurveSystemTest, AssemblesTheSystemThatCeresEvaluates) {
  const Vehicle v = testing::Bx15();
  const testing::MeshedRoad p(
      v,
      testing::SyntheticRoad(80.0, 8.0, [](double s) { return s > 30.0 ? 0.02 : 0.0; },
                             [](double) { return 0.03; }),
      4.0);
  std::vector<StateVector<double>> lambda(p.mesh.size());
  for (size_t k = 0; k < p.mesh.size(); ++k)
    for (int i = 0; i < kNumStates; ++i) lambda[k][i] = 0.01 * std::sin(1.0 + k + 3.0 * i);
  Transcription tr = MakeTranscription(v, p.road, p.mesh, p.qss.x, lambda, p.qss.u, 2);
  ceres::Problem::Options options;
  MidpointCallback callback(&tr);
  options.evaluation_callback = &callback;
  ceres::Problem problem(options);
  BuildProblem(&tr, &problem);

  CurveSystem sys(&tr);
  Eigen::VectorXd F;
  Eigen::SparseMatrix<double> J;
  ASSERT_TRUE(sys.Evaluate(0.05, &F, &J, nullptr));
  tr.weight = WeightFor(0.05);
  std::vector<double> r;
  ceres::CRSMatrix crs;
  ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, &r, nullptr, &crs));

  ASSERT_EQ(F.size(), static_cast<Eigen::Index>(r.size()));
  for (size_t i = 0; i < r.size(); ++i) EXPECT_EQ(F[i], r[i]) << i;
  ASSERT_EQ(J.rows(), crs.num_rows);
  ASSERT_EQ(J.cols(), crs.num_cols);
  ASSERT_EQ(J.cols(), sys.size());
  ASSERT_EQ(J.nonZeros(), static_cast<Eigen::Index>(crs.values.size()));
  EXPECT_EQ(sys.JacobianEntries(), J.nonZeros());
  double largest = 0.0;
  for (int row = 0; row < crs.num_rows; ++row)
    for (int e = crs.rows[row]; e < crs.rows[row + 1]; ++e) {
      EXPECT_EQ(J.coeff(row, crs.cols[e]), crs.values[e]) << row << " " << crs.cols[e];
      largest = std::max(largest, std::abs(crs.values[e]));
    }
  EXPECT_GT(largest, 1.0);  // not a matrix of zeros
}

}  // namespace
}  // namespace ttz::lap
