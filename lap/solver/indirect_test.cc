// The indirect solver on synthetic roads: on a straight, level road it converges through the whole
// barrier continuation, its answer passes the honesty checks, and the lap agrees with the
// quasi-steady lap. Roads with bends, against the Ipopt oracle: oracle_test.cc.
#include "lap/solver/indirect.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>

#include "lap/solver/solution_curve.h"
#include "lap/solver/transcription.h"
#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

using testing::Bx15;
using testing::MeshedRoad;
using testing::StraightRoad;

TEST(IndirectTest, StraightLevelRoadFromAStandingStart) {
  const Vehicle v = Bx15();
  const auto& [road, mesh, qss] = MeshedRoad(v, StraightRoad(300.0), 2.0);
  SolveSummary summary;
  const LapSolution sol =
      SolveIndirect(v, road, mesh, qss.x, {}, qss.u, IndirectOptions{}, &summary);
  ASSERT_TRUE(summary.converged) << summary.message;
  EXPECT_LE(summary.max_residual, 1e-8);
  EXPECT_LE(summary.max_state_defect, 1e-8);
  for (int j = 0; j < kNumConstraints; ++j)
    EXPECT_LE(summary.max_violation[j], 1e-4) << kConstraintNames[j];
  // Acceleration from 5 m/s is limited by the motor current: that constraint is active.
  EXPECT_GT(summary.max_violation[kMotorCurrent], -1e-2);
  EXPECT_NEAR(sol.lap_time, qss.lap_time, 0.01 * qss.lap_time);
  // The barrier slows the lap; removing it (extrapolation to eps = 0) can only speed it up.
  EXPECT_LT(sol.lap_time_extrapolated, sol.lap_time);
  EXPECT_GT(sol.lap_time_extrapolated, 0.99 * sol.lap_time);
  EXPECT_GT(sol.x.back()[kT], sol.x.front()[kT]);  // the motors heat up
  EXPECT_LT(sol.x.back()[kE], sol.x.front()[kE]);  // the pack discharges
}

// The indirect solver on a 300 m straight (2 m mesh) from its QSS guess, with the options `set`
// changes from the defaults; it is expected to converge unless `converges` is false.
LapSolution SolveStraight300(const std::function<void(IndirectOptions*)>& set, SolveSummary* summary,
                             bool converges = true) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  IndirectOptions options;
  set(&options);
  const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, summary);
  EXPECT_EQ(summary->converged, converges) << summary->message;
  return sol;
}

// A continuation that stops other than at a turning point says where its Jacobian is nearly
// singular (|J x| and where the unit x of inverse iteration moves the states): here
// Levenberg-Marquardt's continuation (arclength off) whose second step has one iteration and no
// retry.
TEST(IndirectTest, AStoppedContinuationSaysWhereItsJacobianIsNearestSingular) {
  SolveSummary summary;
  SolveStraight300(
      [](IndirectOptions* o) {
        o->arclength = false;
        o->max_step_iterations = 1;
        o->max_retries = 0;
      },
      &summary, false);
  EXPECT_NE(summary.message.find("continuation failed at eps"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("(its Jacobian nearly singular: |J x| = "), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find(" for the unit x of inverse iteration; the solution moves most in "),
            std::string::npos)
      << summary.message;
}

// From the QSS guess the first solve is of the midpoints' barriers alone, and the node barriers
// are then switched on by the continuation in their share of eps (IndirectOptions::
// node_share_path): the first step with them starts at its solution and takes no iteration of its
// own, and the lap is the one the first step reaches from the midpoints' solution without it (the
// same discrete problem).
TEST(IndirectTest, NodeBarriersSwitchedOnByTheirShareEndOnTheSameLap) {
  SolveSummary by_share, without;
  const LapSolution a = SolveStraight300([](IndirectOptions* o) { o->node_share_path = true; }, &by_share);
  const LapSolution b = SolveStraight300([](IndirectOptions* o) { o->node_share_path = false; }, &without);
  ASSERT_GE(by_share.steps.size(), 2u);
  ASSERT_GE(without.steps.size(), 2u);
  // steps[0]: the midpoints' first solve; steps[1]: the first step with the node barriers
  EXPECT_EQ(by_share.steps[1].eps, by_share.steps[0].eps);
  EXPECT_EQ(by_share.steps[1].iterations, 0);
  EXPECT_GT(without.steps[1].iterations, 0);
  EXPECT_NEAR(a.lap_time, b.lap_time, 1e-7 * b.lap_time);
  EXPECT_NEAR(a.lap_time_extrapolated, b.lap_time_extrapolated, 1e-7 * b.lap_time);
}

// The barrier continuation's correctors stop where a Newton step is longer than
// arclength_contraction_max times the one before; where the path with that bound does not reach
// eps_end within its iterations it is followed again without it, to the lap it reaches without the
// bound, by the same steps from the same start. With a bound of 1e-12 every corrector that needs a
// second Newton step stops, so the path creeps by steps that one step corrects and gives up.
TEST(IndirectTest, AContinuationThatFailsWithTheContractionBoundIsFollowedAgainWithout) {
  SolveSummary unmeetable, without;
  const LapSolution a = SolveStraight300([](IndirectOptions* o) { o->arclength_contraction_max = 1e-12; }, &unmeetable);
  const LapSolution b = SolveStraight300([](IndirectOptions* o) { o->arclength_contraction_max = HUGE_VAL; }, &without);
  const auto failed = [](const SolveSummary& s) {
    return std::count_if(s.steps.begin(), s.steps.end(), [](const ContinuationStep& c) { return !c.converged; });
  };
  EXPECT_GT(failed(unmeetable), failed(without));
  EXPECT_GT(unmeetable.iterations, without.iterations);
  // the last path: the steps without the bound, after its first two (the first solve and the
  // first step with the node barriers)
  ASSERT_GT(without.steps.size(), 2u);
  const size_t offset = unmeetable.steps.size() - without.steps.size();
  for (size_t i = 2; i < without.steps.size(); ++i) {
    EXPECT_EQ(unmeetable.steps[offset + i].eps, without.steps[i].eps) << i;
    EXPECT_EQ(unmeetable.steps[offset + i].converged, without.steps[i].converged) << i;
  }
  EXPECT_EQ(a.eps, b.eps);
  EXPECT_NEAR(a.lap_time, b.lap_time, 1e-9 * b.lap_time);
  EXPECT_NEAR(a.lap_time_extrapolated, b.lap_time_extrapolated, 1e-9 * b.lap_time);
}

// 200 m with a 50 m radius left bend from 80 to 140 m, on a 2 m mesh.
MeshedRoad BendOf200m(const Vehicle& v) {
  return MeshedRoad(v,
                    testing::SyntheticRoad(
                        200.0, 8.0, [](double s) { return s > 80.0 && s < 140.0 ? 0.02 : 0.0; },
                        testing::Zero),
                    2.0);
}

// From the QSS guess Levenberg-Marquardt's first solve hands over to Newton's homotopy once it is
// near (IndirectOptions::homotopy_handoff), and ends on the lap that LM alone reaches (the same
// discrete problem).
TEST(IndirectTest, LevenbergMarquardtHandingOverToNewtonsHomotopyEndsOnTheSameLap) {
  const Vehicle v = Bx15();
  const MeshedRoad p = BendOf200m(v);
  const auto solve = [&](double handoff, SolveSummary* summary, std::string* log) {
    IndirectOptions options;
    options.homotopy_handoff = handoff;
    ::testing::internal::CaptureStderr();
    const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, summary);
    *log = ::testing::internal::GetCapturedStderr();
    EXPECT_TRUE(summary->converged) << summary->message;
    std::cout << "handoff " << handoff << ": first solve " << summary->steps[0].iterations
              << " iterations, in all " << summary->iterations << ", " << summary->solve_seconds
              << " s\n";
    return sol;
  };
  SolveSummary handed, lm;
  std::string handed_log, lm_log;
  const LapSolution a = solve(1.0, &handed, &handed_log);
  const LapSolution b = solve(0.0, &lm, &lm_log);
  EXPECT_NE(handed_log.find("Newton's homotopy from there"), std::string::npos) << handed_log;
  EXPECT_EQ(lm_log.find("Newton's homotopy from there"), std::string::npos) << lm_log;
  EXPECT_NE(handed.steps[0].iterations, lm.steps[0].iterations);
  EXPECT_NEAR(a.lap_time, b.lap_time, 1e-7 * b.lap_time);
  EXPECT_NEAR(a.lap_time_extrapolated, b.lap_time_extrapolated, 1e-7 * b.lap_time);
}

// A first step that fails at eps_start is solved again from the guess at retry_eps_start (the
// 5 km roads need it, docs/lap.md), a window of the first step at 10 eps_start and then at half
// its length; here one Ceres iteration per step makes every step fail.
TEST(IndirectTest, AFailedFirstStepIsRetriedFromTheGuessAtTheRetryWeight) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(100.0), 2.0);
  IndirectOptions options;
  options.max_iterations = 1;
  const auto weights = [&](const IndirectOptions& o) {
    SolveSummary summary;
    SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, o, &summary);
    EXPECT_FALSE(summary.converged);
    std::vector<double> eps;
    for (const ContinuationStep& step : summary.steps) {
      EXPECT_FALSE(step.converged);
      eps.push_back(step.eps);
    }
    return eps;
  };
  // Each try's first solve (the midpoints' barriers alone, SolveFrom) fails, so the nodes' does
  // not start.
  EXPECT_EQ(weights(options), (std::vector<double>{1.0, 0.1}));
  options.retry_eps_start = 0.0;
  EXPECT_EQ(weights(options), (std::vector<double>{1.0}));
  // In windows (IndirectOptions::window_m) a window that fails at eps_start is tried again at ten
  // times the weight; when that fails too, the whole road starts from the guess.
  options.eps_start = 0.1;
  options.window_m = 50.0;
  options.window_overlap_m = 10.0;
  EXPECT_EQ(weights(options), (std::vector<double>{0.1, 1.0, 0.1}));
  // With a window guess, from that guess (at eps_start) before the heavier weight; it gets the
  // window's start state and mesh.
  int calls = 0;
  options.window_guess = [&](const StateVector<double>& start, const std::vector<double>& mesh,
                             std::vector<StateVector<double>>* x, std::vector<ControlVector<double>>* u) {
    ++calls;
    EXPECT_EQ(start, p.qss.x.front());
    EXPECT_EQ(mesh.front(), 0.0);
    EXPECT_GE(mesh.back(), options.window_m);
    EXPECT_LT(mesh.size(), p.mesh.size());
    *x = std::vector<StateVector<double>>(p.qss.x.begin(), p.qss.x.begin() + mesh.size());
    *u = std::vector<ControlVector<double>>(p.qss.u.begin(), p.qss.u.begin() + mesh.size());
  };
  EXPECT_EQ(weights(options), (std::vector<double>{0.1, 0.1, 1.0, 0.1}));
  EXPECT_EQ(calls, 1);
  // A window that fails every try is tried again from the same start at half its length, down to
  // window_min_m: 50 m, then 25 m (its own guess on the shorter mesh), then the whole road.
  options.window_min_m = 20.0;
  calls = 0;
  options.window_guess = [&](const StateVector<double>& start, const std::vector<double>& mesh,
                             std::vector<StateVector<double>>* x,
                             std::vector<ControlVector<double>>* u) {
    EXPECT_EQ(start, p.qss.x.front());
    EXPECT_GE(mesh.back(), ++calls == 1 ? 50.0 : 25.0);
    EXPECT_LT(mesh.back(), calls == 1 ? 60.0 : 30.0);
    *x = std::vector<StateVector<double>>(p.qss.x.begin(), p.qss.x.begin() + mesh.size());
    *u = std::vector<ControlVector<double>>(p.qss.u.begin(), p.qss.u.begin() + mesh.size());
  };
  EXPECT_EQ(weights(options), (std::vector<double>{0.1, 0.1, 1.0, 0.1, 0.1, 1.0, 0.1}));
  EXPECT_EQ(calls, 2);
}

// Windows (IndirectOptions::window_m) of 150 m with 50 m of overlap on the 300 m straight (0-150,
// 100-250 and 200-300 m), each converged at eps_start and followed down to window_eps_end, then
// the continuation on the whole road from their stitched states and costates ends on the lap of
// the unwindowed solve (the same discrete problem); so it does with windows of the first step
// alone (window_eps_end at eps_start). An overlap as long as the window is an error.
TEST(IndirectTest, AFirstStepSolvedInWindowsEndsOnTheSameLap) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  SolveSummary whole;
  const LapSolution a =
      SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, IndirectOptions{}, &whole);
  ASSERT_TRUE(whole.converged) << whole.message;
  IndirectOptions options;
  options.window_m = 150.0;
  options.window_overlap_m = 50.0;
  // The steps with the windows going down to window_eps_end; the lap is the unwindowed one.
  const auto windowed = [&](double window_eps_end) {
    options.window_eps_end = window_eps_end;
    SolveSummary summary;
    const LapSolution b = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, &summary);
    EXPECT_TRUE(summary.converged) << summary.message;
    EXPECT_NEAR(b.lap_time, a.lap_time, 1e-6 * a.lap_time);
    EXPECT_NEAR(b.lap_time_extrapolated, a.lap_time_extrapolated, 1e-6 * a.lap_time);
    return summary.steps;
  };
  const auto at = [](const std::vector<ContinuationStep>& steps, double eps) {
    return std::count_if(steps.begin(), steps.end(),
                         [&](const ContinuationStep& step) { return step.eps == eps; });
  };
  // The windows come first among the steps, each from the retry's weight (0.1;
  // IndirectOptions::window_m). Down to 1e-2: each window's last step and the whole road's first
  // are at 1e-2, and only the windows' first steps (midpoints, then nodes) at 0.1.
  const std::vector<ContinuationStep> down = windowed(1e-2);
  EXPECT_EQ(at(down, 1e-2), 4);
  EXPECT_EQ(at(down, options.retry_eps_start), 6);
  // The first step alone: three windows' first steps and the whole road's at 0.1.
  EXPECT_EQ(at(windowed(options.retry_eps_start), options.retry_eps_start), 7);
  options.window_overlap_m = options.window_m;
  SolveSummary unused;
  EXPECT_THROW(SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, &unused), std::invalid_argument);
}

// A window's answer is the whole road's start, judged by its residuals alone: its constraints are
// the whole road's to meet (SolveFirstStepInWindows, indirect.cc). With a constraint tolerance
// no answer can meet, the windows still stand and the whole road's answer says what is wrong
// with it; before, every window was rejected and the solver started again from the guess.
TEST(IndirectTest, AWindowIsJudgedByItsResidualsAlone) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  IndirectOptions options;
  options.window_m = 150.0;
  options.window_overlap_m = 50.0;
  options.constraint_tolerance = -HUGE_VAL;
  SolveSummary summary;
  SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, &summary);
  EXPECT_FALSE(summary.converged);
  EXPECT_EQ(summary.message.find("a window failed"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("constraint violated by"), std::string::npos) << summary.message;
  EXPECT_LE(summary.max_residual, 10.0 * options.residual_tolerance);
}

// A price p on the charge left at the end (IndirectOptions::end_charge_price_s_per_j) makes the
// solve minimise T - p e(s_N): the end's lambda_e is -p in scaled units, and a dearer charge buys a
// slower lap that leaves more of it. Between the optima at two prices p1 < p2 the lap time per
// joule saved, (T2 - T1) / (e2 - e1), lies in [p1, p2] (each optimum beats the other at its own
// price), up to the barrier's share of the cost (eps_end).
TEST(IndirectTest, APriceOnTheChargeLeftTradesLapTimeForCharge) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  const auto solve = [&](double price) {
    IndirectOptions options;
    options.end_charge_price_s_per_j = price;
    SolveSummary summary;
    const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, &summary);
    EXPECT_TRUE(summary.converged) << summary.message;
    return sol;
  };
  const double p1 = 2e-6, p2 = 4e-6;  // [s/J]: 2 and 4 s/MJ
  const LapSolution free = solve(0.0), a = solve(p1), b = solve(p2);
  EXPECT_EQ(free.lambda.back()[kE], 0.0);
  EXPECT_NEAR(a.lambda.back()[kE], -p1 * DefaultScales(v).state[kE], 1e-12);
  EXPECT_GT(a.x.back()[kE], free.x.back()[kE]);
  EXPECT_GT(b.x.back()[kE], a.x.back()[kE]);
  EXPECT_GT(a.lap_time, free.lap_time);
  const double slope = (b.lap_time - a.lap_time) / (b.x.back()[kE] - a.x.back()[kE]);
  std::cout << "laps " << free.lap_time << ", " << a.lap_time << ", " << b.lap_time << " s; charge left "
            << free.x.back()[kE] << ", " << a.x.back()[kE] << ", " << b.x.back()[kE]
            << " J; slope " << slope << " s/J\n";
  EXPECT_GE(slope, 0.9 * p1);
  EXPECT_LE(slope, 1.1 * p2);
}

// The windows' price (IndirectOptions::window_charge_price_s_per_j) sits at every window's end but
// the last: it changes the windows' answers (each a slower lap of its window) and not the whole
// road's, which has its own free end.
TEST(IndirectTest, ThePriceAtTheWindowsEndsLeavesTheLap) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  const auto solve = [&](double price) {
    IndirectOptions options;
    options.window_m = 150.0;
    options.window_overlap_m = 50.0;
    options.window_charge_price_s_per_j = price;
    SolveSummary summary;
    const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, &summary);
    EXPECT_TRUE(summary.converged) << summary.message;
    return std::make_pair(sol, summary.steps);
  };
  const auto [free, free_steps] = solve(0.0);
  const auto [priced, priced_steps] = solve(4e-6);
  EXPECT_NEAR(priced.lap_time, free.lap_time, 1e-6 * free.lap_time);
  // The first window's first step (steps[0], its midpoints' solve at the same weight) is slower.
  ASSERT_FALSE(free_steps.empty());
  ASSERT_FALSE(priced_steps.empty());
  std::cout << "first window's first step: " << free_steps[0].lap_time << " s free, "
            << priced_steps[0].lap_time << " s priced\n";
  EXPECT_GT(priced_steps[0].lap_time, free_steps[0].lap_time + 1e-4);
}

// Below eps_end (IndirectOptions::eps_floor): a pack of 48 kJ, a ninth of what the road's lap
// at full current takes, ends the lap empty, and at eps_end the relaxed barrier lets the charge
// overshoot zero (7.4e-6 of the pack when this test was written; with 2.5 kJ cells, 0.24 MJ, it
// stays 2.2e-5 inside). With a constraint tolerance below that overshoot the continuation goes
// on down until the charge meets it, and the answer converges; stopped at eps_end (eps_floor =
// eps_end) the same answer says it did not. (Measured: 9.5e-6, 8.9e-6, 6.5e-6, 3.7e-6 and
// 1.9e-6 at eps 5e-5 to 3.1e-6, halving: the overshoot shrinks with eps, but not at once.)
TEST(IndirectTest, AConstraintOvershootAtEpsEndTakesTheContinuationLower) {
  const Vehicle v = Bx15({"battery.cell_energy_j=500"});
  const MeshedRoad p(v, StraightRoad(200.0), 4.0);
  const auto solve = [&](double tolerance, double floor, SolveSummary* summary) {
    IndirectOptions options;
    options.constraint_tolerance = tolerance;
    options.eps_floor = floor;
    return SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, summary);
  };
  const double eps_end = IndirectOptions{}.eps_end;
  SolveSummary at_end;
  const LapSolution first = solve(HUGE_VAL, eps_end, &at_end);
  ASSERT_TRUE(at_end.converged) << at_end.message;
  const double overshoot = at_end.max_violation[kCharge];
  ASSERT_GT(overshoot, 0.0) << "the charge does not overshoot at eps_end: nothing to test";
  const double tolerance = overshoot / 3.0;
  SolveSummary stopped, lower;
  solve(tolerance, eps_end, &stopped);
  EXPECT_FALSE(stopped.converged);
  EXPECT_NE(stopped.message.find("constraint violated by"), std::string::npos) << stopped.message;
  const LapSolution sol = solve(tolerance, IndirectOptions{}.eps_floor, &lower);
  ASSERT_TRUE(lower.converged) << lower.message;
  EXPECT_LE(lower.max_violation[kCharge], tolerance);
  EXPECT_LT(sol.eps, eps_end);
  EXPECT_LE(lower.max_residual, 10.0 * IndirectOptions{}.residual_tolerance);
  // A smaller barrier weight can only speed the lap up, and not by much.
  EXPECT_LT(sol.lap_time, first.lap_time);
  EXPECT_GT(sol.lap_time, 0.999 * first.lap_time);
  std::cout << "charge overshoot " << overshoot << " at eps " << first.eps << ", "
            << lower.max_violation[kCharge] << " at eps " << sol.eps << "; lap " << first.lap_time
            << " -> " << sol.lap_time << " s\n";
}

// A design study's warm start (lap --init): the lap of one gear ratio as the start for another,
// one continuation step above eps_end. With its first step by Newton's homotopy
// (IndirectOptions::homotopy) it ends on the lap solved from the QSS guess (the same discrete
// problem), in fewer iterations than that step by Levenberg-Marquardt took (which here ran into
// max_iterations: 301 against 48 when this test was written).
TEST(IndirectTest, AWarmFirstStepByNewtonsHomotopyEndsOnTheColdLap) {
  const Vehicle v = Bx15();
  const MeshedRoad p(v, StraightRoad(300.0), 2.0);
  SolveSummary first, cold;
  const LapSolution a = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, IndirectOptions{}, &first);
  ASSERT_TRUE(first.converged) << first.message;
  Vehicle geared = v;
  geared.gamma_c *= 1.1;
  const LapSolution c =
      SolveIndirect(geared, p.road, p.mesh, p.qss.x, {}, p.qss.u, IndirectOptions{}, &cold);
  ASSERT_TRUE(cold.converged) << cold.message;
  const auto warm = [&](bool homotopy, SolveSummary* summary) {
    IndirectOptions options;
    options.eps_start = options.eps_end / options.eps_factor;
    options.homotopy = homotopy;
    return SolveIndirect(geared, p.road, p.mesh, a.x, a.lambda, a.u, options, summary);
  };
  SolveSummary by_homotopy, by_lm;
  const LapSolution h = warm(true, &by_homotopy);
  warm(false, &by_lm);
  ASSERT_TRUE(by_homotopy.converged) << by_homotopy.message;
  EXPECT_GT(std::abs(c.lap_time - a.lap_time), 1e-3 * a.lap_time);  // the gear ratio matters
  EXPECT_NEAR(h.lap_time, c.lap_time, 1e-7 * c.lap_time);
  EXPECT_LT(by_homotopy.steps.front().iterations, by_lm.steps.front().iterations);
}

// The lap time at eps = 0, on a path whose lap time is 100 s + 1000 s * eps: through the last two
// steps when they are apart; where the last two are 4e-9 apart and 1e-5 s of rounding separates
// their laps (as where gear 4.2's path stopped, session 52), through the latest step 5 % heavier
// instead, which the last two alone would have put 3.5 s too high.
TEST(IndirectTest, TheLapTimeIsExtrapolatedThroughStepsApart) {
  std::vector<ContinuationStep> steps = {{2e-3, 102.0}, {1e-3, 101.0}};
  EXPECT_NEAR(ExtrapolateLapTime(steps), 100.0, 1e-12);
  steps.push_back({1e-3 - 4e-9, 101.0 + 1e-5});
  EXPECT_NEAR(ExtrapolateLapTime(steps), 100.0, 1e-4);
  EXPECT_DOUBLE_EQ(ExtrapolateLapTime({{1e-3, 101.0}, {0.99e-3, 100.99}}), 100.99);  // none 5 % heavier
  EXPECT_DOUBLE_EQ(ExtrapolateLapTime({{1e-3, 101.0}}), 101.0);
}

// The motor current's switch widened while the barrier is heavy (IndirectOptions::
// current_widening) changes the path, not the answer: below current_model_eps the system is the
// model's, so the lap at eps_end and its extrapolation are those of the path without it. 200 m
// with a bend, where the lap brakes and coasts across the switch.
TEST(IndirectTest, TheWiderSwitchChangesThePathNotTheAnswer) {
  const Vehicle v = Bx15();
  const MeshedRoad p = BendOf200m(v);
  const auto solve = [&](double widening, SolveSummary* summary) {
    IndirectOptions options;
    options.current_widening = widening;
    const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, options, summary);
    EXPECT_TRUE(summary->converged) << summary->message;
    return sol;
  };
  SolveSummary wide, model;
  const LapSolution a = solve(3.0, &wide);
  const LapSolution b = solve(1.0, &model);
  ASSERT_FALSE(wide.steps.empty());
  ASSERT_FALSE(model.steps.empty());
  // the first step, at eps_start, solves a wider switch: a different lap
  EXPECT_GT(std::abs(wide.steps[0].lap_time - model.steps[0].lap_time), 1e-6 * b.lap_time);
  EXPECT_NEAR(a.lap_time, b.lap_time, 1e-7 * b.lap_time);
  // the extrapolation goes through steps at other weights on the two paths (1.3e-7 apart here)
  EXPECT_NEAR(a.lap_time_extrapolated, b.lap_time_extrapolated, 1e-6 * b.lap_time);
}

// A barrier continuation step whose tangent turns by more than arclength_max_turn_rad is not taken
// but retried at half its length (FollowPath): with a limit of 0.05 rad the 300 m straight's path
// retries steps it takes without the limit, and ends on the same lap.
TEST(IndirectTest, AStepThatTurnsTooSharplyIsRetriedShorter) {
  SolveSummary tight, free;
  const LapSolution a = SolveStraight300([](IndirectOptions* o) { o->arclength_max_turn_rad = 0.05; }, &tight);
  const LapSolution b = SolveStraight300([](IndirectOptions* o) { o->arclength_max_turn_rad = HUGE_VAL; }, &free);
  const auto retried = [](const SolveSummary& s) {
    return std::count_if(s.steps.begin(), s.steps.end(), [](const ContinuationStep& c) { return !c.converged; });
  };
  EXPECT_GT(retried(tight), retried(free));
  EXPECT_GT(tight.steps.size(), free.steps.size());
  EXPECT_NEAR(a.lap_time, b.lap_time, 1e-7 * b.lap_time);
}

// From an answer with the motor current's switch widened, ToModelSwitch takes the transcription
// to the answer with the model's switch at the same weight: the answer the continuation reaches
// with the widening off. 200 m with a bend at eps 1e-2, where the switch is three times wider.
TEST(IndirectTest, ToModelSwitchGoesToTheModelsAnswerAtTheSameWeight) {
  const Vehicle v = Bx15();
  const MeshedRoad p = BendOf200m(v);
  IndirectOptions options;
  options.eps_end = options.eps_floor = 1e-2;
  const auto solve = [&](double widening) {
    IndirectOptions o = options;
    o.current_widening = widening;
    SolveSummary summary;
    const LapSolution sol = SolveIndirect(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, o, &summary);
    EXPECT_TRUE(summary.converged) << summary.message;
    return sol;
  };
  const LapSolution wide = solve(3.0), model = solve(1.0);
  EXPECT_GT(std::abs(wide.lap_time - model.lap_time), 1e-7 * model.lap_time);
  Transcription tr = MakeTranscription(v, p.road, p.mesh, wide.x, wide.lambda, wide.u, 2);
  tr.weight = WeightFor(options.eps_end);
  tr.current_model_eps = options.current_model_eps;
  const auto max_residual = [&](double widening) {
    tr.current_widening = widening;
    double max_all = 0.0, max_state = 0.0;
    ResidualLevels(&tr, &max_all, &max_state);
    return max_all;
  };
  EXPECT_LE(max_residual(3.0), 10.0 * options.residual_tolerance);  // the widened answer
  EXPECT_GT(max_residual(1.0), 1e3 * options.residual_tolerance);   // is not the model's
  tr.current_widening = 3.0;
  ContinuationStep step;
  ASSERT_TRUE(ToModelSwitch(options, &tr, options.eps_end, &step));
  EXPECT_TRUE(step.converged);
  EXPECT_GT(step.iterations, 0);
  EXPECT_EQ(tr.current_widening, 1.0);
  EXPECT_LE(max_residual(1.0), 10.0 * options.residual_tolerance);
  EXPECT_NEAR(step.lap_time, model.lap_time, 1e-7 * model.lap_time);
}

}  // namespace
}  // namespace ttz::lap
