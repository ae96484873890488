// What one step of a collocation scheme (lap/solver/collocation.h: the implicit midpoint rule of
// both solvers, Radau IIA with 2 and 3 stages) misses on a lap's trajectory, before a solver is
// built on it (docs/lap.md "Re-simulation", "What another scheme would buy"). Not a test.
//
// Coarse intervals are every EVERY-th mesh interval of LAP.h5 (a lap of ROAD, e.g. at --dt-max
// 0.1) up to LENGTH_M. On each, from the lap's state at the interval's start, one step of each
// scheme with the controls at its stages taken from the lap (linear in s through its node
// controls) is compared with the RK4 integration of the same start under the same controls (the
// polynomial through the stage values) in steps of at most 0.5 ms at the start's speed: the
// scheme's local error, the part of the re-simulation check's difference (lap/resimulate.h) that
// one interval makes. Printed per scheme and state: the largest error [% of the state's scale,
// ResimStateScales] and the share of intervals over 0.1 %. KEY=VALUE arguments override bike.yaml
// values as `lap --set` does.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/parse_number.h"
#include "common/road_artefact.h"
#include "lap/bike.h"
#include "lap/lap_artefact.h"
#include "lap/model/dynamics.h"
#include "lap/resimulate.h"
#include "lap/solver/collocation.h"

namespace {

using namespace ttz::lap;
using Vec = Eigen::Matrix<double, kNumStates, 1>;

constexpr double kRk4StepSeconds = 5e-4;  // the wheel's slip mode decays at up to ~1100 /s

// x' = f(x, u(s), road(s)) with the controls of a step: the polynomial through the stage values.
struct StepModel {
  const Vehicle& v;
  const RoadTrack& road;
  const ButcherTableau& tab;
  double s0, h;
  std::vector<ControlVector<double>> stage_u;

  ControlVector<double> U(double s) const {
    const double tau = (s - s0) / h;
    ControlVector<double> u{};
    for (int j = 0; j < tab.Stages(); ++j) {
      double l = 1.0;
      for (int m = 0; m < tab.Stages(); ++m)
        if (m != j) l *= (tau - tab.c[m]) / (tab.c[j] - tab.c[m]);
      for (int i = 0; i < kNumControls; ++i) u[i] += l * stage_u[j][i];
    }
    return u;
  }

  template <typename T>
  bool Slope(double s, const ControlVector<double>& u, const Eigen::Matrix<T, kNumStates, 1>& x,
             Eigen::Matrix<T, kNumStates, 1>* dx) const {
    StateVector<T> xs;
    ControlVector<T> ut;
    for (int i = 0; i < kNumStates; ++i) xs[i] = x[i];
    for (int i = 0; i < kNumControls; ++i) ut[i] = T(u[i]);
    const ModelPoint<T> m = EvaluateModel(v, xs, ut, road.At(s));
    if (!(m.kin.sdot > 0.0)) return false;
    for (int i = 0; i < kNumStates; ++i) (*dx)[i] = m.dx_ds[i];
    return true;
  }

  // The scheme's right-hand side: stage j's controls.
  template <typename T>
  bool operator()(double s, int stage, const Eigen::Matrix<T, kNumStates, 1>& x,
                  Eigen::Matrix<T, kNumStates, 1>* dx) const {
    return Slope(s, stage_u[stage], x, dx);
  }

  // RK4 over the step in `steps` equal steps.
  bool Integrate(const Vec& x0, int steps, Vec* x1) const {
    Vec x = x0, k1, k2, k3, k4;
    const double d = h / steps;
    for (int k = 0; k < steps; ++k) {
      const double s = s0 + k * d;
      if (!Slope(s, U(s), x, &k1) || !Slope(s + d / 2, U(s + d / 2), Vec(x + d / 2 * k1), &k2) ||
          !Slope(s + d / 2, U(s + d / 2), Vec(x + d / 2 * k2), &k3) || !Slope(s + d, U(s + d), Vec(x + d * k3), &k4))
        return false;
      x += d / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    *x1 = x;
    return x.allFinite();
  }
};

void Run(const ButcherTableau& tab, const Vehicle& v, const RoadTrack& road, const WarmStart& lap,
         const Vec& scale, int every, double length) {
  Vec largest = Vec::Zero(), over = Vec::Zero();
  int intervals = 0, failed = 0;
  double seconds = 0.0, rk4_check = 0.0;
  for (size_t k = 0; k + every < lap.s.size() && lap.s[k + every] <= length; k += every) {
    Vec x0;
    for (int i = 0; i < kNumStates; ++i) x0[i] = lap.x[k][i];
    StepModel model{v, road, tab, lap.s[k], lap.s[k + every] - lap.s[k], {}};
    std::vector<double> stages;
    for (double c : tab.c) stages.push_back(model.s0 + c * model.h);
    model.stage_u = ResampleWarmStart(lap, v, stages).u;  // the node controls, linear in s
    const double dt = model.h / std::max(x0[kV], 1.0);
    const int steps = std::max(8, static_cast<int>(std::ceil(dt / kRk4StepSeconds)));
    Vec scheme, exact, exact2;
    if (!CollocationStep<kNumStates>(tab, model, model.s0, model.h, x0, scale, &scheme) ||
        !model.Integrate(x0, steps, &exact)) {
      ++failed;
      continue;
    }
    if (intervals == 0 && model.Integrate(x0, 2 * steps, &exact2))
      rk4_check = ((exact2 - exact).array() / scale.array()).abs().maxCoeff();
    ++intervals;
    seconds += dt;
    const Vec error = ((scheme - exact).array() / scale.array()).abs();
    largest = largest.cwiseMax(error);
    over += (error.array() > 1e-3).cast<double>().matrix();
  }
  std::printf("%-8s every %d: %d intervals (mean %.3f s), %d steps failed; RK4 at half its step: %.1e\n",
              tab.name.c_str(), every, intervals, seconds / std::max(intervals, 1), failed, rk4_check);
  std::printf("  largest [%%] (share over 0.1 %% [%%]):");
  for (int i = 0; i < kNumStates; ++i)
    std::printf(" %s %.2g (%.1f)", kStateNames[i], 100.0 * largest[i], 100.0 * over[i] / std::max(intervals, 1));
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: collocation_bench ROAD.h5 BIKE.yaml LAP.h5 EVERY LENGTH_M [KEY=VALUE ...]\n");
    return 2;
  }
  try {
    const std::vector<std::string> overrides(argv + 6, argv + argc);
    const Vehicle v = MakeVehicle(LoadBike(argv[2], overrides));
    const RoadTrack road(ttz::ReadRoad(argv[1]));
    const WarmStart lap = ReadLapForWarmStart(argv[3]);
    const std::optional<int> every = ttz::ParseInt(argv[4]);
    const std::optional<double> length = ttz::ParseDouble(argv[5]);
    if (!every || *every < 1 || !length) throw std::invalid_argument("EVERY (an integer >= 1) or LENGTH_M not a number");
    LapSolution sol;
    sol.s = lap.s;
    sol.x = lap.x;
    const StateVector<double> scales = ResimStateScales(v, sol);
    const Vec scale = Eigen::Map<const Vec>(scales.data());
    for (const char* name : {"midpoint", "radau2", "radau3"})
      Run(TableauByName(name), v, road, lap, scale, *every, *length);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "collocation_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
