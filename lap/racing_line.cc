#include "lap/racing_line.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <stdexcept>

namespace ttz::lap {

RacingLine ComputeRacingLine(const RoadTrack& road, const std::vector<double>& mesh,
                             double border_margin_m, const RacingLineOptions& options) {
  const int nodes = static_cast<int>(mesh.size());
  RacingLine line;
  line.n.assign(nodes, 0.0);
  line.dn_ds.assign(nodes, 0.0);
  line.kappa.resize(nodes);
  std::vector<double> kappa(nodes), bound(nodes);  // road curvature; the largest |n| (RacingLineOptions)
  for (int k = 0; k < nodes; ++k) {
    const RoadPoint p = road.At(mesh[k]);
    kappa[k] = p.kappa;
    bound[k] = options.width_share * std::max(0.0, 0.5 * p.width - border_margin_m);
    // The solver starts from the start offset (where the width allows): where the minimum is
    // not unique, e.g. on a straight, that offset is kept.
    line.n[k] = k == 0 ? options.start_offset_m : std::clamp(options.start_offset_m, -bound[k], bound[k]);
  }
  if (nodes >= 3) {
    ceres::Problem problem;
    for (int k = 1; k + 1 < nodes; ++k) {
      auto* cost = new ceres::AutoDiffCostFunction<PathCurvatureResidual, 1, 1, 1, 1>(
          new PathCurvatureResidual{kappa[k], mesh[k] - mesh[k - 1], mesh[k + 1] - mesh[k]});
      problem.AddResidualBlock(cost, nullptr, &line.n[k - 1], &line.n[k], &line.n[k + 1]);
    }
    for (int k = 1; k + 2 < nodes; ++k) {
      auto* cost = new ceres::AutoDiffCostFunction<PathCurvatureChangeResidual, 1, 1, 1, 1, 1>(
          new PathCurvatureChangeResidual{kappa[k], kappa[k + 1], mesh[k] - mesh[k - 1],
                                          mesh[k + 1] - mesh[k], mesh[k + 2] - mesh[k + 1],
                                          options.curvature_change_length_m});
      problem.AddResidualBlock(cost, nullptr, &line.n[k - 1], &line.n[k], &line.n[k + 1], &line.n[k + 2]);
    }
    problem.SetParameterBlockConstant(&line.n[0]);
    for (int k = 1; k < nodes; ++k) {
      problem.SetParameterLowerBound(&line.n[k], 0, -bound[k]);
      problem.SetParameterUpperBound(&line.n[k], 0, bound[k]);
    }
    ceres::Solver::Options o;
    o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    o.max_num_iterations = 200;
    o.function_tolerance = 1e-12;
    ceres::Solver::Summary summary;
    ceres::Solve(o, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE)
      throw std::runtime_error("racing line: " + summary.message);
  }
  for (int k = 0; k < nodes; ++k) {
    const int a = std::max(0, k - 1), b = std::min(nodes - 1, k + 1);
    line.dn_ds[k] = a == b ? 0.0 : (line.n[b] - line.n[a]) / (mesh[b] - mesh[a]);
    const double second =
        k > 0 && k + 1 < nodes ? SecondDifference(line.n[k - 1], line.n[k], line.n[k + 1],
                                                  mesh[k] - mesh[k - 1], mesh[k + 1] - mesh[k])
                               : 0.0;
    line.kappa[k] = kappa[k] / (1.0 - line.n[k] * kappa[k]) + second;
  }
  return line;
}

}  // namespace ttz::lap
