// The Ipopt oracle: its midpoint derivatives (Jets for the Jacobian, HyperDual numbers for the Hessian
// of the Lagrangian) against central differences, and its lap on a straight level road against the
// indirect solver's.
#include "lap/solver/ipopt_direct.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "lap/model/constraints.h"
#include "lap/solver/direct_node.h"
#include "lap/solver/indirect.h"
#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

using testing::Bx15;
using testing::MeshedRoad;
using testing::StraightRoad;

// Ipopt with the constraints at the midpoints only (what the nodes change).
IpoptOptions MidpointsOnly() {
  IpoptOptions o;
  o.node_constraints = false;
  return o;
}

// A node in a right-hand bend on a climbing, twisting road, at a state off any steady state and
// controls near the tyre's limit, with a random (seeded) perturbation.
struct NodeFixture {
  Vehicle v = Bx15();
  DirectNode node{&v, DefaultScales(v), RoadPoint{}};
  NodePoint z;
  NodeFixture() {
    node.road.kappa = 0.02;
    node.road.dkappa = 1e-3;
    node.road.nu = 0.002;
    node.road.tau = -0.001;
    node.road.sigma = 0.04;
    node.road.width = 8.0;
    const StateVector<double> x = {1.2, 0.03, 22.0, 0.02, 0.014, 0.5, 75.0, 48.0,
                                   0.7 * v.pack.e_i, 0.2, 0.02};
    const ControlVector<double> u = {0.4, 120.0};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    for (int i = 0; i < kNumStates; ++i) z(i) = x[i] / node.sc.state[i] + jitter(rng);
    for (int i = 0; i < kNumControls; ++i)
      z(kNumStates + i) = u[i] / node.sc.control[i] + jitter(rng);
  }
};

// |a - b| <= 1e-5 of the largest |b| in the row (or 1e-9).
void ExpectRowsNear(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, const char* what) {
  for (int r = 0; r < b.rows(); ++r) {
    const double scale = std::max(1e-9, b.row(r).cwiseAbs().maxCoeff());
    for (int c = 0; c < b.cols(); ++c)
      EXPECT_NEAR(a(r, c), b(r, c), 1e-5 * scale) << what << " (" << r << ", " << c << ")";
  }
}

// The Jacobian J of y(z) and the Hessian H of w^T y (random w) that `derivatives(z, &y, &J)` and
// `hessian(z, w, &H)` give, against central differences of y and of J^T w.
template <typename Point, typename Values, typename Jacobian, typename Hessian, typename D,
          typename HF>
void ExpectDerivativesMatchDifferences(const Point& z, D derivatives, HF hessian) {
  Values y, w;
  Jacobian J;
  ASSERT_TRUE(derivatives(z, &y, &J));
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int o = 0; o < w.size(); ++o) w(o) = normal(rng);
  Hessian H;
  ASSERT_TRUE(hessian(z, w, &H));

  const double step = 1e-5;
  Eigen::MatrixXd J_num(y.size(), z.size()), H_num(z.size(), z.size());
  for (int c = 0; c < z.size(); ++c) {
    Point zp = z, zm = z;
    zp(c) += step;
    zm(c) -= step;
    Values yp, ym;
    Jacobian Jp, Jm;
    ASSERT_TRUE(derivatives(zp, &yp, &Jp));
    ASSERT_TRUE(derivatives(zm, &ym, &Jm));
    J_num.col(c) = (yp - ym) / (2 * step);
    H_num.col(c) = (Jp.transpose() * w - Jm.transpose() * w) / (2 * step);
  }
  ExpectRowsNear(J, J_num, "Jacobian");
  ExpectRowsNear(H, H_num, "Hessian");
}

TEST(IpoptDirectTest, NodeJacobianAndHessianMatchCentralDifferences) {
  const NodeFixture f;
  ExpectDerivativesMatchDifferences<NodePoint, NodeOutputs, NodeJacobian, NodeHessian>(
      f.z, [&](const NodePoint& z, NodeOutputs* y, NodeJacobian* J) { return NodeDerivatives(f.node, z, y, J); },
      [&](const NodePoint& z, const NodeOutputs& w, NodeHessian* H) {
        return NodeWeightedHessian(f.node, z, w, H);
      });
}

TEST(IpoptDirectTest, NodeConstraintJacobianAndHessianMatchCentralDifferences) {
  const NodeFixture f;
  const StatePoint x = f.z.head<kNumStates>();
  ExpectDerivativesMatchDifferences<StatePoint, NodeConstraintValues, NodeConstraintJacobian,
                                    StateHessian>(
      x,
      [&](const StatePoint& z, NodeConstraintValues* g, NodeConstraintJacobian* J) {
        return NodeConstraints(f.node, z, g, J);
      },
      [&](const StatePoint& z, const NodeConstraintValues& w, StateHessian* H) {
        return NodeConstraintsWeightedHessian(f.node, z, w, H);
      });
}

// The largest g_j over the nodes 1..N of a lap (node 0 is the given start).
double WorstNodeViolation(const Vehicle& v, const RoadTrack& road, const LapSolution& sol) {
  double worst = -HUGE_VAL;
  for (size_t k = 1; k < sol.s.size(); ++k)
    for (double g : StateConstraints(v, sol.x[k], road.At(sol.s[k]))) worst = std::max(worst, g);
  return worst;
}

// A 50 m radius bend (the oracle's bend road, 300 m, 2 m mesh). With the constraints at the
// midpoints alone, the roll rate and the tyre's ellipse overshoot their limits at nodes between
// two midpoints where they bind (measured 4-6 %); with the node constraints (the default) no node
// is over, at a lap a little slower.
TEST(IpoptDirectTest, NodeConstraintsKeepEveryNodeWithinItsLimits) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v,
                     testing::SyntheticRoad(
                         300.0, 8.0,
                         [](double s) {
                           return std::min({1.0, std::max(0.0, (s - 100.0) / 20.0),
                                            std::max(0.0, (220.0 - s) / 20.0)}) / 50.0;
                         },
                         testing::Zero),
                     2.0);
  const auto solve = [&](const IpoptOptions& options, SolveSummary* summary) {
    return SolveDirectIpopt(v, p.road, p.mesh, p.qss.x, p.qss.u, options, summary);
  };
  SolveSummary nodes_summary, mid_summary;
  const LapSolution nodes = solve(IpoptOptions{}, &nodes_summary);
  const LapSolution mid = solve(MidpointsOnly(), &mid_summary);
  ASSERT_TRUE(nodes_summary.converged) << nodes_summary.message;
  ASSERT_TRUE(mid_summary.converged) << mid_summary.message;
  EXPECT_GT(WorstNodeViolation(v, p.road, mid), 1e-2);
  EXPECT_LE(WorstNodeViolation(v, p.road, nodes), 1e-4);
  EXPECT_GE(nodes.lap_time, mid.lap_time - 1e-6);
  EXPECT_LT(nodes.lap_time, mid.lap_time * 1.005);
  std::cout << "bend: midpoints only " << mid.lap_time << " s (" << mid_summary.iterations
            << " iterations), with nodes " << nodes.lap_time << " s (" << nodes_summary.iterations
            << ")\n";
}

// An option value Ipopt rejects would otherwise leave its default in force without a word.
TEST(IpoptDirectTest, AnOptionIpoptRejectsIsAnError) {
  const Vehicle v = Bx15();
  const auto& [road, mesh, qss] = MeshedRoad(v, StraightRoad(50.0), 5.0);
  const auto solve = [&](const IpoptOptions& options) {
    SolveSummary summary;
    SolveDirectIpopt(v, road, mesh, qss.x, qss.u, options, &summary);
  };
  IpoptOptions no_tolerance;
  no_tolerance.tolerance = 0.0;  // Ipopt's range: tol > 0
  EXPECT_THROW(solve(no_tolerance), std::invalid_argument);
  IpoptOptions unknown_strategy;
  unknown_strategy.mu_strategy = "sometimes";
  EXPECT_THROW(solve(unknown_strategy), std::invalid_argument);
  IpoptOptions unknown_globalization;
  unknown_globalization.mu_globalization = "sometimes";
  EXPECT_THROW(solve(unknown_globalization), std::invalid_argument);
  IpoptOptions no_barrier;
  no_barrier.mu_init = 0.0;  // Ipopt's range: mu_init > 0
  EXPECT_THROW(solve(no_barrier), std::invalid_argument);
  EXPECT_NO_THROW(solve(IpoptOptions{}));
}

// IpoptOptions::extra reaches Ipopt by name, typed as Ipopt registers the name, after (and so
// over) the options of its own fields; what Ipopt would not take is an error.
TEST(IpoptDirectTest, ExtraOptionsAreSetByNameAndOverrideTheFields) {
  const Vehicle v = Bx15();
  const auto& [road, mesh, qss] = MeshedRoad(v, StraightRoad(50.0), 5.0);
  const auto solve = [&](std::vector<std::pair<std::string, std::string>> extra) {
    IpoptOptions options;
    options.extra = std::move(extra);
    SolveSummary summary;
    SolveDirectIpopt(v, road, mesh, qss.x, qss.u, options, &summary);
    return summary;
  };
  EXPECT_THROW(solve({{"no_such_option", "1"}}), std::invalid_argument);
  EXPECT_THROW(solve({{"mumps_pivtol", "small"}}), std::invalid_argument);   // a number
  EXPECT_THROW(solve({{"mumps_pivtol", "2"}}), std::invalid_argument);       // range 0..1
  EXPECT_THROW(solve({{"max_iter", "1.5"}}), std::invalid_argument);         // an integer
  EXPECT_THROW(solve({{"mu_strategy", "sometimes"}}), std::invalid_argument);
  const SolveSummary full = solve({{"mumps_pivtol", "1e-5"}, {"mu_strategy", "adaptive"}});
  EXPECT_TRUE(full.converged) << full.message;
  const SolveSummary one = solve({{"max_iter", "1"}});  // over IpoptOptions::max_iterations
  EXPECT_FALSE(one.converged);
  EXPECT_LE(one.iterations, 1);
  EXPECT_LT(one.iterations, full.iterations);
}

// Both solvers start from the QSS guess, which is symmetric (n = alpha = phi = 0), and stay on
// the symmetric (straight-line) solution. It is a saddle of this model: from a guess perturbed by
// 1 mm in n, Ipopt finds a lap that weaves across the road, leaning +-0.5 rad, 0.85 % faster
// (10.854 s against 10.945 s; 0.6 % at a 0.5 m mesh): under the motor-current limit the smaller
// rolling radius of the leaned tyre (tyre.h, R_e) gears the wheel down.
TEST(IpoptDirectTest, StraightLevelRoadAgreesWithTheIndirectSolver) {
  const Vehicle v = Bx15();
  const auto& [road, mesh, qss] = MeshedRoad(v, StraightRoad(300.0), 2.0);
  SolveSummary summary;
  const LapSolution sol = SolveDirectIpopt(v, road, mesh, qss.x, qss.u, MidpointsOnly(), &summary);
  ASSERT_TRUE(summary.converged) << summary.message;
  EXPECT_LE(summary.max_state_defect, 1e-6);
  for (int j = 0; j < kNumConstraints; ++j)
    EXPECT_LE(summary.max_violation[j], 1e-4) << kConstraintNames[j];
  EXPECT_GT(summary.max_violation[kMotorCurrent], -1e-6);  // the current limit is active
  EXPECT_LT(sol.lap_time, qss.lap_time * 1.01);

  // The indirect solver on the same midpoint-only problem (the costates then have no jumps at
  // the nodes to compare).
  IndirectOptions midpoints;
  midpoints.node_constraints = false;
  SolveSummary indirect_summary;
  const LapSolution indirect =
      SolveIndirect(v, road, mesh, qss.x, {}, qss.u, midpoints, &indirect_summary);
  ASSERT_TRUE(indirect_summary.converged) << indirect_summary.message;
  // Same transcription (implicit midpoint, one control per interval) on the same mesh: the laps
  // agree within 0.05 % (issue 3); measured 4e-7 relative (10.943536 s against 10.943531 s
  // extrapolated to eps = 0).
  EXPECT_NEAR(sol.lap_time, indirect.lap_time_extrapolated, 5e-4 * indirect.lap_time_extrapolated);
  // The costates from Ipopt's multipliers are the indirect solver's (up to its barrier's share at
  // eps = 1e-4): measured within 0.1 % of the largest.
  double largest = 0.0;
  for (const StateVector<double>& l : indirect.lambda)
    for (double li : l) largest = std::max(largest, std::abs(li));
  for (size_t k = 0; k < mesh.size(); ++k)
    for (int i = 0; i < kNumStates; ++i)
      EXPECT_NEAR(sol.lambda[k][i], indirect.lambda[k][i], 0.005 * largest)
          << kStateNames[i] << " at s = " << mesh[k];
}

}  // namespace
}  // namespace ttz::lap
