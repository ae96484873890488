// Cost of one interval of each solver, in CPU microseconds per call. The Ipopt transcription's
// midpoint (lap/solver/direct_node.h): the values y(z), the Jacobian dy/dz (Jets) and the Hessian
// of w^T y (second derivatives); Ipopt evaluates each once per interval and iteration, and the
// Hessian dominates its time (docs/lap.md, "Bounds and HyperDual Hessians"). The indirect
// solver's (lap/solver/node.h, node_barrier.h): a midpoint's controls and F, G with or without
// their derivatives (the control Newton started at its answer, as in a converged continuation),
// and a node's barrier with its gradient or its Hessian too; a Jacobian of the indirect system
// costs one midpoint and one node barrier with derivatives per interval.
//
//   node_bench BIKE.yaml [CALLS]
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>

#include "lap/bike.h"
#include "lap/solver/direct_node.h"
#include "lap/solver/node.h"
#include "lap/solver/node_barrier.h"

namespace {

using ttz::lap::NodePoint;

// CPU microseconds per call of f(), over `calls` calls (CPU time, so that other processes on the
// machine do not count).
template <typename F>
double MicrosecondsPerCall(int calls, F f) {
  const std::clock_t start = std::clock();
  for (int i = 0; i < calls; ++i) f();
  return 1e6 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / calls;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ttz::lap;
  if (argc < 2) {
    std::fprintf(stderr, "usage: node_bench BIKE.yaml [CALLS]\n");
    return 2;
  }
  const int calls = argc > 2 ? std::atoi(argv[2]) : 2000;
  const Vehicle v = MakeVehicle(LoadBike(argv[1]));
  DirectNode node{&v, DefaultScales(v), RoadPoint{}};
  node.road.kappa = 0.02;  // a climbing, twisting right-hand bend
  node.road.dkappa = 1e-3;
  node.road.nu = 0.002;
  node.road.tau = -0.001;
  node.road.sigma = 0.04;
  node.road.width = 8.0;
  const StateVector<double> x = {1.2, 0.03, 42.0, 0.02, 0.014, 0.5,  142.0,
                                 48.0, 0.7 * v.pack.e_i, 0.2, 0.02, 0.3, 100.0};
  const ControlVector<double> u = {0.4, 120.0};
  NodePoint z;
  for (int i = 0; i < kNumStates; ++i) z(i) = x[i] / node.sc.state[i];
  for (int i = 0; i < kNumControls; ++i) z(kNumStates + i) = u[i] / node.sc.control[i];
  NodeOutputs y, w;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> weight(-1.0, 1.0);
  for (int o = 0; o < kNumNodeOutputs; ++o) w(o) = weight(rng);
  NodeJacobian J;
  NodeHessian H;
  bool ok = true;
  const double t_values = MicrosecondsPerCall(calls, [&] { ok &= NodeValues(node, z, &y); });
  const double t_jacobian = MicrosecondsPerCall(calls, [&] { ok &= NodeDerivatives(node, z, &y, &J); });
  const double t_hessian = MicrosecondsPerCall(calls, [&] { ok &= NodeWeightedHessian(node, z, w, &H); });
  if (!ok) {
    std::fprintf(stderr, "node_bench: the model is undefined at the bench point\n");
    return 1;
  }
  std::printf("Ipopt, per midpoint [CPU us]: values %.2f, Jacobian %.2f, Hessian %.2f (%d calls "
              "each)\n", t_values, t_jacobian, t_hessian, calls);
  // The indirect solver at the same point, with costates of a braking bike's size (scaled).
  const BarrierWeight barrier_weight{1e-2, 1e-3};
  StateVector<double> xs, lambda;
  for (int i = 0; i < kNumStates; ++i) {
    xs[i] = z(i);
    lambda[i] = 0.01 * weight(rng);
  }
  NodeData mid;
  mid.u_start = {z(kNumStates), z(kNumStates + 1)};
  EvaluateNode(v, node.sc, node.road, barrier_weight, xs, lambda, false, &mid);
  // Its Newton for u* starts, as in the solver, from u* of the last accepted iterate, which the
  // states have moved from since: here 1e-3 (scaled) off in each control.
  mid.u_start = {mid.u[0] + 1e-3, mid.u[1] - 1e-3};
  NodeBarrierData barrier;
  const double length_m = 5.0;
  const double t_mid = MicrosecondsPerCall(calls, [&] {
    EvaluateNode(v, node.sc, node.road, barrier_weight, xs, lambda, false, &mid);
  });
  const double t_mid_d = MicrosecondsPerCall(calls, [&] {
    EvaluateNode(v, node.sc, node.road, barrier_weight, xs, lambda, true, &mid);
  });
  const double t_bar = MicrosecondsPerCall(calls, [&] {
    EvaluateNodeBarrier(v, node.sc, node.road, barrier_weight, length_m, xs, false, &barrier);
  });
  const double t_bar_d = MicrosecondsPerCall(calls, [&] {
    EvaluateNodeBarrier(v, node.sc, node.road, barrier_weight, length_m, xs, true, &barrier);
  });
  if (!mid.valid || !mid.control_converged || !barrier.valid) {
    std::fprintf(stderr, "node_bench: the indirect node is undefined at the bench point\n");
    return 1;
  }
  std::printf("indirect, per midpoint [CPU us]: values %.2f, with derivatives %.2f; per node "
              "barrier: gradient %.2f, with Hessian %.2f\n", t_mid, t_mid_d, t_bar, t_bar_d);
  return 0;
}
