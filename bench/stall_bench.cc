// Where a barrier continuation stopped (docs/lap_log.md "Session 52"):
// the square system of the indirect solver (CurveSystem) rebuilt at the unknowns and barrier
// weight of LAP.h5 (a lap of ROAD; a failed one holds its last converged point), and printed:
// - its largest residual and where it sits;
// - the tangent of the solution curve, dv/d log eps, and where it moves the states most;
// - a unit vector x that its Jacobian J maps to nearly zero (NearNullVector: inverse iteration),
//   |J x| and where x moves the states: a near-null direction that Newton cannot resolve;
// - Newton at the file's weight and 2 % below it (12 iterations, to 1e-8: the tolerance of the
//   continuation's last step).
// KEY=VALUE arguments override bike.yaml values as `lap --set` does (the bike the lap was solved
// with). Not a test.
#include <Eigen/Core>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/road_artefact.h"
#include "lap/bike.h"
#include "lap/lap_artefact.h"
#include "lap/solver/solution_curve.h"
#include "lap/solver/sparse_lu.h"

namespace {

using namespace ttz::lap;

// The transcription of the lap's unknowns on its mesh, with its intervals' controls as the
// Newton starts of the control elimination (as the design sensitivities do, lap/sensitivity.cc).
Transcription LapTranscription(const Vehicle& v, const RoadTrack& road, const WarmStart& lap) {
  const SolverGuess g = ResampleWarmStart(lap, v, lap.s);
  Transcription tr = MakeTranscription(v, road, lap.s, g.x, g.lambda, g.u, 2);
  tr.StartControlsAt(g.u_interval);
  return tr;
}

// Newton at eps from the unknowns and control starts in `sys`, which it leaves as they were.
void NewtonFrom(CurveSystem* sys, double eps, const char* what) {
  const Eigen::VectorXd start = sys->Get();
  const std::vector<NodeData> mids = sys->transcription()->mids;
  double residual = 0.0;
  int iterations = 0;
  const bool ok = NewtonAtFixedEps(sys, eps, 1e-8, 12, &residual, &iterations);
  std::printf("Newton at %s (eps %.6g): %s in %d iterations, max residual %.3e\n", what, eps,
              ok ? "converged" : "FAILED", iterations, residual);
  sys->Set(start);
  sys->transcription()->mids = mids;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: stall_bench ROAD.h5 BIKE.yaml LAP.h5 [KEY=VALUE ...]\n");
    return 2;
  }
  try {
    const std::vector<std::string> overrides(argv + 4, argv + argc);
    const Vehicle v = MakeVehicle(LoadBike(argv[2], overrides));
    const RoadTrack road(ttz::ReadRoad(argv[1]));
    const WarmStart lap = ReadLapForWarmStart(argv[3]);
    if (!(lap.eps > 0.0)) throw std::invalid_argument(std::string(argv[3]) + ": no barrier weight (an Ipopt lap?)");
    Transcription tr = LapTranscription(v, road, lap);
    CurveSystem sys(&tr);
    Eigen::VectorXd F, Fp, x;
    Eigen::SparseMatrix<double> J;
    if (!sys.Evaluate(lap.eps, &F, &J, &Fp)) throw std::runtime_error("the system cannot be evaluated there");
    double max_all = 0.0, max_state = 0.0;
    ResidualPeak peak;
    ResidualLevels(&tr, &max_all, &max_state, &peak);
    std::printf("%d unknowns at eps %.6g: max residual %.3e at %s\n", sys.size(), lap.eps, max_all,
                DescribePeak(tr, peak).c_str());
    if (!SolveSquare(J, CurveSystem::kJacobianForm, -Fp, &x)) throw std::runtime_error("J is singular");
    std::printf("tangent dv/d log eps: norm %.3e; %s\n", x.norm(), sys.DescribeStateDirection(x).c_str());
    double shrunk = 0.0;
    if (!NearNullVector(J, CurveSystem::kJacobianForm, kNearNullIterations, &x, &shrunk))
      throw std::runtime_error("J is singular");
    std::printf("near-null vector x of J (inverse iteration): |J x| = %.3e; %s\n", shrunk,
                sys.DescribeStateDirection(x).c_str());
    NewtonFrom(&sys, lap.eps, "the file's weight");
    NewtonFrom(&sys, 0.98 * lap.eps, "2 % below");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stall_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
