// The indirect solver against the Ipopt oracle (issue 3, "Oracle agreement"): on the same road
// and the same mesh the two lap times agree within 0.05 %, at the indirect solver's final barrier
// weight and, tighter, after its extrapolation to eps = 0. The indirect answer also passes the
// honesty checks at eps = 1e-4 and every constraint holds, at the midpoints and at the nodes (both
// solvers constrain both: node_barrier.h, IpoptOptions::node_constraints). A saved reference
// solution guards the road's lap time and both solvers' iteration counts. Tests only (gtest).
#pragma once

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "common/road_artefact.h"
#include "lap/solver/indirect.h"
#include "lap/solver/ipopt_direct.h"
#include "lap/testing/problem.h"

namespace ttz::lap::testing {

struct OracleCase {
  const char* name;
  RoadArtefact road;
  double extrapolated_tolerance;  // on |extrapolated / Ipopt - 1|
  // A saved reference solution (measured by the test itself, both solvers with the nodes
  // constrained): Ipopt's lap time, and iteration counts that either solver exceeding by more
  // than a quarter is a regression.
  double reference_lap_s;
  int ipopt_iterations, indirect_iterations;
  double ds_m = 2.0;  // uniform mesh [m]
  std::vector<std::string> bike_overrides = {};  // section.key=value on Bx15()
};

// Solves `road` on its mesh with both solvers and compares their lap times; returns the indirect
// solver's answer.
inline LapSolution ExpectAgreement(const OracleCase& c) {
  const Vehicle v = Bx15(c.bike_overrides);
  const auto& [road, mesh, qss] = MeshedRoad(v, c.road, c.ds_m);
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

}  // namespace ttz::lap::testing
