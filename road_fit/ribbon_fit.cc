#include "road_fit/ribbon_fit.h"

#include <ceres/ceres.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "common/error.h"
#include "common/log.h"
#include "road_fit/initial_guess.h"
#include "road_fit/ribbon_costs.h"
#include "road_fit/road_profile.h"
#include "road_fit/station.h"

namespace ttz::road {
namespace {

constexpr double kSideSign[] = {+1.0, -1.0, 0.0};  // Side::kLeft, kRight, kCentre (eq. 7)

// The observations of one side, with their index in RoadInput::points.
struct SidePoints {
  std::vector<Observation> points;
  std::vector<size_t> index;
};

std::array<SidePoints, 3> SplitBySide(const RoadInput& input) {
  std::array<SidePoints, 3> sides;
  for (size_t i = 0; i < input.points.size(); ++i) {
    auto& side = sides[static_cast<int>(input.points[i].side)];
    side.points.push_back(input.points[i]);
    side.index.push_back(i);
  }
  return sides;
}

// Station of every input point, in input order.
std::vector<Station> Stations(const Ribbon& ribbon, const std::array<SidePoints, 3>& sides, size_t count) {
  std::vector<Station> stations(count);
  for (const SidePoints& side : sides) {
    const std::vector<Station> found = ProjectOntoRibbon(ribbon, side.points);
    for (size_t i = 0; i < found.size(); ++i) stations[side.index[i]] = found[i];
  }
  return stations;
}

class ProgressCallback : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(Progress* progress) : progress_(progress) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    progress_->Update(s.iteration, s.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Progress* progress_;
};

// Sets the banking states and control to zero, for a fit that holds them there (ribbon.h).
void Level(Ribbon* ribbon) {
  for (auto& x : ribbon->x) x[kXi] = x[kXiHat] = 0.0;
  for (auto& u : ribbon->u) u[kUXi] = 0.0;
}

// The residuals of the dynamics, the smoothness and a circuit's closure, over the first N states
// (ribbon.h); s(0) = 0 (eq. 4c) held.
template <int N>
void AddDynamicsAndSmoothness(const FitOptions& options, Ribbon* ribbon, ceres::Problem* problem) {
  constexpr int M = ControlsFor(N);
  const long n = static_cast<long>(ribbon->u.size());
  for (long k = 0; k < n; ++k) {
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<DynamicsDefect<N>, N, N, N, M>(
                                  new DynamicsDefect<N>(ribbon->h, options.defect_tolerance)),
                              nullptr, ribbon->x[k].data(), ribbon->x[k + 1].data(), ribbon->u[k].data());
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ControlEffort<M>, M, M>(
                                  new ControlEffort<M>(options.smoothing_weight * ribbon->h, options.control_reference)),
                              nullptr, ribbon->u[k].data());
  }
  if (ribbon->closed) {
    const double turns = std::round((ribbon->x[n][kTheta] - ribbon->x[0][kTheta]) / (2.0 * M_PI));
    RibbonScales closure_tol = options.defect_tolerance;  // per metre -> absolute, over one node spacing
    for (double& t : closure_tol) t *= ribbon->h;
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<Closure<N>, Closure<N>::kNumResiduals, N, N>(
                                  new Closure<N>(turns, closure_tol)),
                              nullptr, ribbon->x[0].data(), ribbon->x[n].data());
  }
  problem->SetManifold(ribbon->x[0].data(), new ceres::SubsetManifold(N, {kS}));
}

// The measured points, widths and (when N has the banking) bankings.
template <int N>
void AddObservations(const RoadInput& input, const std::vector<Station>& stations, const FitOptions& options,
                     Ribbon* ribbon, ceres::Problem* problem) {
  for (size_t i = 0; i < input.points.size(); ++i) {
    const Observation& o = input.points[i];
    const Station& st = stations[i];
    double* x0 = ribbon->x[st.interval].data();
    double* x1 = ribbon->x[st.interval + 1].data();
    ceres::LossFunction* loss = options.robust ? new ceres::CauchyLoss(options.robust_scale) : nullptr;
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<BorderDistance<N>, 3, N, N>(new BorderDistance<N>(
            st.t, kSideSign[static_cast<int>(o.side)], {o.x_m, o.y_m, o.z_m},
            {options.sigma_lateral_m, options.sigma_vertical_m, options.sigma_along_m})),
        loss, x0, x1);
    if (o.side == Side::kCentre && std::isfinite(o.width_m))
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<StateObservation, 1, N, N>(
                                    new StateObservation(kWidth, st.t, o.width_m, options.sigma_width_m)),
                                nullptr, x0, x1);
    if constexpr (N > kXi)
      if (std::isfinite(o.banking_rad))
        problem->AddResidualBlock(new ceres::AutoDiffCostFunction<StateObservation, 1, N, N>(
                                      new StateObservation(kXi, st.t, o.banking_rad, options.sigma_banking_rad)),
                                  nullptr, x0, x1);
  }
}

ceres::Solver::Summary SolvePass(const RoadInput& input, const std::vector<Station>& stations,
                                 const FitOptions& options, bool warm, Ribbon* ribbon, Progress* progress) {
  ceres::Problem problem;
  // Without banking data xi would be a free constant (or fitted to noise): it is held at zero,
  // out of the problem.
  if (options.level || !input.carries_banking) {
    Level(ribbon);
    AddDynamicsAndSmoothness<kLevelStates>(options, ribbon, &problem);
    AddObservations<kLevelStates>(input, stations, options, ribbon, &problem);
  } else {
    AddDynamicsAndSmoothness<kNumRibbonStates>(options, ribbon, &problem);
    AddObservations<kNumRibbonStates>(input, stations, options, ribbon, &problem);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;  // CHOLMOD: faster here than Eigen's
                                                               // (docs/lap_log.md "Eigen's sparse Cholesky")
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = options.num_threads;
  solver.function_tolerance = 1e-7;  // relative cost change; smaller only moved the TT fit by millimetres
  // The problem is nearly linear near the answer: large trust regions make Levenberg-Marquardt
  // take Gauss-Newton steps (measured: 46 instead of 84 iterations on 20 km of the TT course).
  solver.initial_trust_region_radius = warm ? 1e12 : 1e8;
  solver.gradient_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-10;
  ProgressCallback callback(progress);
  solver.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  Log(LogKind::kDebug, summary.FullReport());
  return summary;
}

// Largest collocation defects of positions [m] and angles [rad] over all intervals.
void MaxDefects(const Ribbon& ribbon, FitSummary* summary) {
  RibbonScales unit;
  unit.fill(1.0 / ribbon.h);  // DynamicsDefect divides by h * tol: this makes it the raw defect
  const DynamicsDefect<> defect(ribbon.h, unit);
  summary->max_defect_position_m = summary->max_defect_angle_rad = 0.0;
  for (size_t k = 0; k < ribbon.u.size(); ++k) {
    double r[kNumRibbonStates];
    defect(ribbon.x[k].data(), ribbon.x[k + 1].data(), ribbon.u[k].data(), r);
    for (int j : {kX, kY, kZ}) summary->max_defect_position_m = std::max(summary->max_defect_position_m, std::abs(r[j]));
    for (int j : {kTheta, kSigma, kXi}) summary->max_defect_angle_rad = std::max(summary->max_defect_angle_rad, std::abs(r[j]));
  }
}

void PointResiduals(const RoadInput& input, const std::vector<Station>& stations, const Ribbon& ribbon,
                    FitSummary* summary) {
  summary->residuals.clear();
  double sum2 = 0.0;
  summary->max_distance_m = 0.0;
  for (size_t i = 0; i < input.points.size(); ++i) {
    const Observation& o = input.points[i];
    const Station& st = stations[i];
    const BorderDistance<> unit_distance(st.t, kSideSign[static_cast<int>(o.side)], {o.x_m, o.y_m, o.z_m}, {1, 1, 1});
    double r[3];
    unit_distance(ribbon.x[st.interval].data(), ribbon.x[st.interval + 1].data(), r);
    const double s = (1 - st.t) * ribbon.x[st.interval][kS] + st.t * ribbon.x[st.interval + 1][kS];
    summary->residuals.push_back({o.line, o.side, s, r[0], r[1], r[2]});
    const double d = std::hypot(r[0], r[1]);
    sum2 += d * d;
    if (d > summary->max_distance_m) {
      summary->max_distance_m = d;
      summary->max_distance_line = o.line;
    }
  }
  summary->rms_distance_m = std::sqrt(sum2 / std::max<size_t>(1, input.points.size()));
}

// Whether the road is fitted as a circuit: as asked, or (kAuto) when its ends are close. A circuit
// asked for whose ends are far apart is an input error, one with a smaller gap a warning.
bool IsClosed(const RoadInput& input, const CentrePolyline& centre, const FitOptions& options) {
  const double gap = EndsGap(centre);
  if (options.topology == Topology::kAuto) return gap < options.closure_gap_m;
  if (options.topology == Topology::kOpen) return false;
  char text[200];
  std::snprintf(text, sizeof text, "the road's ends are %.0f m apart", gap);
  if (std::round(gap) > options.max_closing_gap_m) {  // as printed: never "300 m apart, at most 300 m"
    char limit[120];
    std::snprintf(limit, sizeof limit, ", too far for --closed (a circuit's ends meet; at most %.0f m is bridged)",
                  options.max_closing_gap_m);
    throw InputError(input.file, std::string(text) + limit + ": drop --closed, or give the whole circuit");
  }
  if (gap >= options.closure_gap_m)
    Log(LogKind::kWarning, input.file + ": " + text + "; --closed bridges them with a straight");
  return true;
}

}  // namespace

void SetControlsFromStates(Ribbon* ribbon) {
  ribbon->u.resize(ribbon->x.size() - 1);
  for (size_t k = 0; k < ribbon->u.size(); ++k) {
    const auto& a = ribbon->x[k];
    const auto& b = ribbon->x[k + 1];
    ribbon->u[k] = {(b[kThetaHat] - a[kThetaHat]) / ribbon->h, (b[kSigmaHat] - a[kSigmaHat]) / ribbon->h,
                    (b[kWidth] - a[kWidth]) / ribbon->h, 0.0, (b[kXiHat] - a[kXiHat]) / ribbon->h};
  }
}

Ribbon FitRibbon(const RoadInput& input, const FitOptions& options, FitSummary* summary) {
  const CentrePolyline centre = RoughCentre(input);
  const bool closed = IsClosed(input, centre, options);
  // The first pass runs on a coarser grid (cheaper, and it is the one that needs many iterations);
  // the next ones on the requested spacing.
  Ribbon ribbon = InitialRibbon(centre, options.ds_m * options.first_pass_coarsening, closed);
  const auto sides = SplitBySide(input);
  Progress progress("ribbon fit");
  *summary = FitSummary();
  std::vector<Station> stations;
  bool all_converged = true;
  for (int pass = 0; pass < options.projection_passes; ++pass) {
    // zeta := s of the previous pass, so that the stretch u_s starts at zero and its penalty does
    // not hold the length at the first estimate's.
    if (pass > 0) ribbon = RibbonFromProfile(SampleRibbon(ribbon, options.ds_m));
    stations = Stations(ribbon, sides, input.points.size());
    const ceres::Solver::Summary s = SolvePass(input, stations, options, pass > 0, &ribbon, &progress);
    if (pass == 0) summary->initial_cost = s.initial_cost;
    summary->final_cost = s.final_cost;
    summary->iterations += static_cast<int>(s.iterations.size()) - 1;
    summary->termination = s.message;
    all_converged = all_converged && s.termination_type == ceres::CONVERGENCE;
    ++summary->passes;
  }
  summary->solve_seconds = progress.ElapsedSeconds();
  MaxDefects(ribbon, summary);
  PointResiduals(input, stations, ribbon, summary);
  summary->converged = all_converged && summary->max_defect_position_m < 1e-2 && summary->max_defect_angle_rad < 1e-3;
  return ribbon;
}

std::string FitSummary::BriefReport() const {
  char text[512];
  std::snprintf(text, sizeof text,
                "%s after %d passes, %d iterations, %.2f s; cost %.6g -> %.6g; point distance rms %.3f m, max %.3f m "
                "(line %ld); max defect %.2e m, %.2e rad",
                converged ? "converged" : "NOT CONVERGED", passes, iterations, solve_seconds, initial_cost, final_cost,
                rms_distance_m, max_distance_m, max_distance_line, max_defect_position_m, max_defect_angle_rad);
  return text;
}

}  // namespace ttz::road
