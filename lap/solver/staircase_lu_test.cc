// The staircase LU (staircase_lu.h) against Eigen's dense LU on random matrices of the form, with
// the transcription's layout and the corner cases of the first group's width; and its refusals.
#include "lap/solver/staircase_lu.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "lap/solver/solution_curve.h"
#include "lap/testing/random_staircase.h"

namespace ttz::lap {
namespace {

using testing::RandomStaircase;

void ExpectSolvesLikeDenseLu(int R, int g, int N) {
  const Eigen::SparseMatrix<double> J = RandomStaircase(R, g, N, 11 * R + g);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(J.rows(), -1.0, 2.0);
  StaircaseLU lu({R, g});
  ASSERT_TRUE(lu.Compute(J));
  const Eigen::VectorXd x = lu.Solve(b);
  const Eigen::VectorXd dense = Eigen::MatrixXd(J).partialPivLu().solve(b);
  EXPECT_LE((x - dense).lpNorm<Eigen::Infinity>(), 1e-9 * dense.lpNorm<Eigen::Infinity>())
      << "R " << R << " g " << g;
  EXPECT_LE((J * x - b).lpNorm<Eigen::Infinity>(), 1e-10 * dense.lpNorm<Eigen::Infinity>());
}

TEST(StaircaseLuTest, TheTranscriptionsForm) {
  const Staircase form = CurveSystem::kJacobianForm;
  ExpectSolvesLikeDenseLu(form.block_rows, form.first_width, 12);
}

TEST(StaircaseLuTest, FirstGroupsOfEveryWidth) {
  for (int g = 0; g <= 5; ++g) ExpectSolvesLikeDenseLu(5, g, 9);
}

TEST(StaircaseLuTest, OneBlock) { ExpectSolvesLikeDenseLu(6, 2, 1); }

TEST(StaircaseLuTest, RefusesAnEntryOutsideTheStaircase) {
  Eigen::SparseMatrix<double> J = RandomStaircase(4, 2, 5, 3);
  StaircaseLU lu({4, 2});
  ASSERT_TRUE(lu.Compute(J));
  J.coeffRef(0, 19) = 1.0;  // row block 0 in the last group
  EXPECT_FALSE(lu.Compute(J));
  // 20 rows: not in blocks of 3
  EXPECT_FALSE(StaircaseLU({3, 2}).Compute(RandomStaircase(4, 2, 5, 3)));
}

TEST(StaircaseLuTest, RefusesASingularMatrix) {
  Eigen::SparseMatrix<double> J = RandomStaircase(4, 2, 5, 5);
  // column 9 made zero
  for (Eigen::SparseMatrix<double>::InnerIterator it(J, 9); it; ++it) it.valueRef() = 0.0;
  EXPECT_FALSE(StaircaseLU({4, 2}).Compute(J));
}

}  // namespace
}  // namespace ttz::lap
