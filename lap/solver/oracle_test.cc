// The indirect solver against the Ipopt oracle (issue 3, "Oracle agreement"): on the same roads
// and the same mesh the two lap times agree within 0.05 %, at the indirect solver's final barrier
// weight and, tighter, after its extrapolation to eps = 0. Each indirect answer also passes the
// honesty checks at eps = 1e-4 and every constraint holds, at the midpoints and at the nodes (both
// solvers constrain both: node_barrier.h, IpoptOptions::node_constraints). Saved reference
// solutions guard each road's lap time and both solvers' iteration counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "lap/solver/indirect.h"
#include "lap/solver/ipopt_direct.h"
#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct OracleCase {
  const char* name;
  RoadArtefact road;
  double extrapolated_tolerance;  // on |extrapolated / Ipopt - 1|
  // A saved reference solution (measured in session 7, both solvers with the nodes
  // constrained): Ipopt's lap time, and iteration counts that either solver exceeding by more
  // than a quarter is a regression.
  double reference_lap_s;
  int ipopt_iterations, indirect_iterations;
  double ds_m = 2.0;  // uniform mesh [m]
};

// Solves `road` on its mesh with both solvers and compares their lap times; returns the indirect
// solver's answer.
LapSolution ExpectAgreement(const OracleCase& c) {
  const Vehicle v = testing::Bx15();
  const auto& [road, mesh, qss] = testing::MeshedRoad(v, c.road, c.ds_m);
  SolveSummary indirect_summary, oracle_summary;
  const LapSolution sol =
      SolveIndirect(v, road, mesh, qss.x, {}, qss.u, IndirectOptions{}, &indirect_summary);
  const LapSolution oracle =
      SolveDirectIpopt(v, road, mesh, qss.x, qss.u, IpoptOptions{}, &oracle_summary);
  std::cout << c.name << ": indirect " << sol.lap_time << " s at eps " << sol.eps
            << ", extrapolated " << sol.lap_time_extrapolated << " s, "
            << indirect_summary.iterations << " iterations, " << indirect_summary.solve_seconds
            << " s; Ipopt " << oracle.lap_time << " s, " << oracle_summary.iterations
            << " iterations; QSS " << qss.lap_time << " s\n";
  EXPECT_TRUE(indirect_summary.converged) << indirect_summary.message;
  EXPECT_TRUE(oracle_summary.converged) << oracle_summary.message;
  EXPECT_LE(indirect_summary.max_residual, 1e-8);
  EXPECT_EQ(indirect_summary.control_failures, 0);
  for (int j = 0; j < kNumConstraints; ++j)
    EXPECT_LE(indirect_summary.max_violation[j], 0.0) << kConstraintNames[j];  // barrier keeps inside
  EXPECT_DOUBLE_EQ(sol.eps, 1e-4);
  EXPECT_NEAR(sol.lap_time / oracle.lap_time, 1.0, 5e-4);  // issue 3: within 0.05 %
  EXPECT_NEAR(sol.lap_time_extrapolated / oracle.lap_time, 1.0, c.extrapolated_tolerance);
  EXPECT_LT(sol.lap_time, qss.lap_time);
  EXPECT_NEAR(oracle.lap_time, c.reference_lap_s, 1e-4 * c.reference_lap_s);
  EXPECT_LE(oracle_summary.iterations, 1.25 * c.ipopt_iterations);
  EXPECT_LE(indirect_summary.iterations, 1.25 * c.indirect_iterations);
  return sol;
}

TEST(OracleTest, BendLeaningIntoIt) {
  // 300 m with a 50 m radius left bend from 100 to 220 m, ramped in and out over 20 m. With
  // Omega_z and tau_w as controls the continuation stalled at eps ~ 0.03 here (H concave in
  // Omega_z, a singular brake torque: lap/model/state.h, docs/lap.md); as states it goes all the
  // way.
  const LapSolution sol = ExpectAgreement(
      {"bend, 300 m",
       testing::SyntheticRoad(300.0, 8.0,
                              [](double s) {
                                return std::min({1.0, std::max(0.0, (s - 100.0) / 20.0),
                                                 std::max(0.0, (220.0 - s) / 20.0)}) /
                                       50.0;
                              },
                              testing::Zero),
       5e-5, 14.3317, 47, 361});
  // The bike leans into the left bend (phi < 0 in the model's frame, y right).
  const size_t apex = sol.x.size() * 160 / 300;
  ASSERT_LT(apex, sol.x.size());
  EXPECT_LT(sol.x[apex][kPhi], -0.3);
}

TEST(OracleTest, SBendsOverACrestAndADip) {
  // Sinusoidal S-bends (50 m smallest radius) over a 4 % crest and dip.
  ExpectAgreement({"S-bends with slope, 400 m",
                   testing::SyntheticRoad(
                       400.0, 8.0, [](double s) { return 0.02 * std::sin(2 * kPi * s / 200); },
                       [](double s) { return 0.04 * std::sin(2 * kPi * s / 300); }),
                   1e-4, 19.4312, 23, 352});
}

TEST(OracleTest, HairpinOnADescent) {
  // A 15 m radius hairpin (about 180 degrees), ramped over 10 m at each end, on a 6 % descent.
  ExpectAgreement(
      {"hairpin on a descent, 200 m",
       testing::SyntheticRoad(
           200.0, 8.0,
           [](double s) { return std::clamp(std::min(s - 60.0, 130.0 - s) / 10.0, 0.0, 1.0) / 15.0; },
           [](double) { return std::atan(-0.06); }),
       1e-4, 13.1716, 33, 342});
}

// The curvature of a bend of radius `radius_m` (positive left), full from s0 to s1 and ramped
// from zero over the 20 m before s0 and after s1 [1/m] (bends that meet overlap their ramps).
double Bend(double s, double s0, double s1, double radius_m) {
  return std::clamp(std::min(s - s0, s1 - s) / 20.0 + 1.0, 0.0, 1.0) / radius_m;
}

// 5 km of straights, fast sweepers, S-bends, a 20 m hairpin and two tight bends over hills of up
// to 6 % slope.
RoadArtefact MixedRoad5km() {
  const auto kappa = [](double s) {
    return Bend(s, 400, 560, 80) + Bend(s, 900, 1000, -60) + Bend(s, 1000, 1100, 60) +
           Bend(s, 1500, 1560, 20) + Bend(s, 2200, 2500, -200) + Bend(s, 3000, 3150, 40) +
           Bend(s, 3150, 3300, -40) + Bend(s, 3800, 3860, 25) + Bend(s, 4300, 4600, 150);
  };
  const auto sigma = [](double s) {
    return 0.04 * std::sin(2 * kPi * s / 1500) + 0.02 * std::sin(2 * kPi * s / 700);
  };
  return testing::SyntheticRoad(5000.0, 8.0, kappa, sigma);
}

// The oracle alone on the mixed road, in every ctest run: a saved reference solution (measured in
// session 8) of its lap time and iterations on a 5 m mesh, honest and no slower than the QSS lap.
TEST(OracleTest, MixedRoad5kmIpoptReference) {
  const Vehicle v = testing::Bx15();
  const auto& [road, mesh, qss] = testing::MeshedRoad(v, MixedRoad5km(), 5.0);
  SolveSummary summary;
  const LapSolution sol = SolveDirectIpopt(v, road, mesh, qss.x, qss.u, IpoptOptions{}, &summary);
  std::cout << "mixed road, 5 km: Ipopt " << sol.lap_time << " s, " << summary.iterations
            << " iterations, " << summary.solve_seconds << " s; QSS " << qss.lap_time << " s\n";
  ASSERT_TRUE(summary.converged) << summary.message;
  EXPECT_LE(summary.max_state_defect, 1e-6);
  for (int j = 0; j < kNumConstraints; ++j)
    EXPECT_LE(summary.max_violation[j], 1e-4) << kConstraintNames[j];
  EXPECT_LT(sol.lap_time, qss.lap_time);
  EXPECT_NEAR(sol.lap_time, 159.242, 1e-4 * 159.242);
  EXPECT_LE(summary.iterations, 1.25 * 87);
}

// Both solvers on the mixed road (5 m mesh). The indirect solver's first step fails at eps = 1
// and converges from the guess at eps = 0.1 (IndirectOptions::retry_eps_start). Measured in
// session 10 (this test): indirect 159.304 s at eps 1e-4 (+0.039 %), 159.279 s extrapolated
// (+0.023 %), 794 iterations (301 of them the failed first step at eps 1), 1001 s with two
// full-course laps on the machine. Too long for ctest: `make -C bench oracle` runs it
// (docs/lap.md).
TEST(OracleTest, DISABLED_MixedRoad5kmAgreement) {
  ExpectAgreement({"mixed road, 5 km", MixedRoad5km(), 5e-4, 159.242, 87, 794, 5.0});
}

}  // namespace
}  // namespace ttz::lap
