// The interval residual blocks of the midpoint transcription: their Jacobians (assembled from each
// midpoint's total derivatives through u*) against central differences of the residuals, with the
// midpoints and node barriers re-evaluated at every perturbed point, on a road with a bend and a
// slope.
#include "lap/solver/transcription.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "lap/testing/problem.h"
#include "lap/testing/synthetic_road.h"

namespace ttz::lap {
namespace {

std::array<double, kW> Residual(Transcription* tr, int k) {
  std::array<double, kW> r{};
  const double* p[2] = {tr->W(k), tr->W(k + 1)};
  IntervalResidual(tr, k).Evaluate(p, r.data(), nullptr);
  return r;
}

// 60 m climbing at 3 % into a 50 m radius bend from 20 m, on a 2 m mesh.
testing::MeshedRoad BendOnAClimb(const Vehicle& v) {
  return testing::MeshedRoad(
      v,
      testing::SyntheticRoad(60.0, 8.0, [](double s) { return s > 20.0 ? 0.02 : 0.0; },
                             [](double) { return 0.03; }),
      2.0);
}

// Its transcription at eps 0.1 from the QSS states, with costates that vary along the road and
// between the states.
Transcription TranscriptionOf(const Vehicle& v, const testing::MeshedRoad& p) {
  std::vector<StateVector<double>> lambda(p.mesh.size());
  for (size_t k = 0; k < p.mesh.size(); ++k)
    for (int i = 0; i < kNumStates; ++i) lambda[k][i] = 0.01 * std::sin(1.0 + k + 3.0 * i);
  Transcription tr = MakeTranscription(v, p.road, p.mesh, p.qss.x, lambda, p.qss.u, 1);
  tr.weight = {0.1, 1e-3};
  return tr;
}

TEST(TranscriptionTest, IntervalJacobiansMatchCentralDifferences) {
  const Vehicle v = testing::Bx15();
  const testing::MeshedRoad p = BendOnAClimb(v);
  Transcription tr = TranscriptionOf(v, p);
  for (int k : {0, 12, 28, 29}) {  // 29: the last interval, with all of node N's barrier
    tr.EvaluateMids(true);
    ASSERT_TRUE(tr.all_valid);
    std::array<double, 2 * kW * kW> jac{};
    double* J[2] = {jac.data(), jac.data() + kW * kW};
    std::array<double, kW> r{};
    const double* p[2] = {tr.W(k), tr.W(k + 1)};
    ASSERT_TRUE(IntervalResidual(&tr, k).Evaluate(p, r.data(), J));
    for (int side = 0; side < 2; ++side)
      for (int j = 0; j < kW; ++j) {
        double* x = tr.W(k + side) + j;
        const double x0 = *x, step = 1e-6;
        *x = x0 + step;
        tr.EvaluateMids(false);
        const std::array<double, kW> rp = Residual(&tr, k);
        *x = x0 - step;
        tr.EvaluateMids(false);
        const std::array<double, kW> rm = Residual(&tr, k);
        *x = x0;
        for (int i = 0; i < kW; ++i) {
          const double fd = (rp[i] - rm[i]) / (2.0 * step);
          const double an = J[side][i * kW + j];
          EXPECT_NEAR(an, fd, 1e-5 + 1e-4 * std::abs(fd))
              << "interval " << k << " side " << side << " residual " << i << " unknown " << j;
        }
      }
  }
}

// The node barriers' share theta of eps (Transcription::node_share): at 0 the system is the one
// without node barriers (the midpoints' barriers weigh eps and the nodes' nothing), the start of
// the continuation that switches them on (NodeBarrierPath); in between it differs from both.
TEST(TranscriptionTest, NodeBarriersWithoutAShareLeaveTheMidpointsSystem) {
  const Vehicle v = testing::Bx15();
  const testing::MeshedRoad p = BendOnAClimb(v);
  Transcription tr = TranscriptionOf(v, p);
  const auto residuals = [&](bool node_barriers, double share) {
    tr.node_barriers = node_barriers;
    tr.node_share = share;
    tr.EvaluateMids(false);
    EXPECT_TRUE(tr.all_valid);
    std::vector<double> r;
    for (int k = 0; k + 1 < tr.NumNodes(); ++k) {
      const std::array<double, kW> rk = Residual(&tr, k);
      r.insert(r.end(), rk.begin(), rk.end());
    }
    return r;
  };
  const std::vector<double> midpoints = residuals(false, 1.0), none = residuals(true, 0.0),
                            half = residuals(true, 0.5), full = residuals(true, 1.0);
  double most = 0.0, half_off = 0.0;
  for (size_t i = 0; i < midpoints.size(); ++i) {
    EXPECT_NEAR(none[i], midpoints[i], 1e-12 * (1.0 + std::abs(midpoints[i]))) << i;
    most = std::max(most, std::abs(full[i] - midpoints[i]));
    half_off = std::max(half_off, std::abs(half[i] - full[i]));
  }
  EXPECT_GT(most, 1e-6);      // the node barriers matter here
  EXPECT_GT(half_off, 1e-6);  // and half of them is not all of them
}

// The solver's failure messages name where the largest residual sits (ResidualPeak): the
// component it names holds the largest |residual|, and a node's speed costate pushed far off
// shows up in the costate equation of V of one of the node's two intervals.
TEST(TranscriptionTest, TheResidualPeakIsWhereTheSystemIsOff) {
  const Vehicle v = testing::Bx15();
  const testing::MeshedRoad p(v, testing::SyntheticRoad(60.0, 8.0, [](double) { return 0.0; }, [](double) { return 0.0; }),
                              2.0);
  Transcription tr = MakeTranscription(v, p.road, p.mesh, p.qss.x, {}, p.qss.u, 1);
  tr.weight = {0.1, 1e-3};
  double max_all = 0.0, max_state = 0.0;
  ResidualPeak peak;
  ResidualLevels(&tr, &max_all, &max_state, &peak);
  ASSERT_GE(peak.interval, 0);
  EXPECT_EQ(std::abs(Residual(&tr, peak.interval)[peak.component]), max_all);

  tr.W(15)[kNumStates + kV] += 1e3 * max_all;  // scaled costate of V
  ResidualLevels(&tr, &max_all, &max_state, &peak);
  EXPECT_TRUE(peak.interval == 14 || peak.interval == 15) << peak.interval;
  EXPECT_EQ(peak.component, kNumStates + kV);
  EXPECT_EQ(DescribePeak(tr, peak).rfind("the costate equation of V on ", 0), 0u) << DescribePeak(tr, peak);
}

// The motor current's smoothing width along the continuation (Transcription::ModelAtWeight):
// current_widening times the model's at and above current_widening x current_model_eps, the
// model's at and below current_model_eps, in proportion to eps between; off at widening 1.
TEST(TranscriptionTest, TheMotorCurrentsSwitchWidensWithTheWeight) {
  const Vehicle v = testing::Bx15();
  const testing::MeshedRoad p = BendOnAClimb(v);
  Transcription tr = TranscriptionOf(v, p);
  const double d = v.smoothing.current;
  const auto width_at = [&](double eps) {
    tr.weight.eps = eps;
    return tr.ModelAtWeight().smoothing.current;
  };
  EXPECT_EQ(width_at(1.0), d);  // off by default
  tr.current_widening = 3.0;
  tr.current_model_eps = 3e-4;
  EXPECT_EQ(width_at(1.0), 3.0 * d);
  EXPECT_EQ(width_at(9e-4), 3.0 * d);
  EXPECT_NEAR(width_at(6e-4), 2.0 * d, 1e-12 * d);
  EXPECT_EQ(width_at(3e-4), d);
  EXPECT_EQ(width_at(1e-4), d);
  EXPECT_EQ(tr.ModelAtWeight().motor.i_m0, v.motor.i_m0);  // nothing else changes
  // and the midpoints see it: the motor heats by i_m^2 R_m, and a wider switch draws more current
  // where the lap coasts or brakes (here at eps 1, widened 3x against the model's)
  tr.weight = {1.0, 1e-3};
  tr.EvaluateMids(false);
  std::vector<NodeData> wide = tr.mids;
  tr.current_widening = 1.0;
  tr.EvaluateMids(false);
  double largest = 0.0;
  for (size_t k = 0; k < wide.size(); ++k)
    largest = std::max(largest, std::abs(wide[k].F[kT] - tr.mids[k].F[kT]));
  EXPECT_GT(largest, 0.0);
}

}  // namespace
}  // namespace ttz::lap
