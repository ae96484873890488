#include "road_fit/road_output.h"

#include <cmath>
#include <cstdio>

#include "common/artefact.h"

namespace ttz::road {
namespace {

void AddGeographic(const LocalFrame& frame, RoadArtefact* road) {
  const auto add = [&](double x, double y, std::vector<double>* lat, std::vector<double>* lon) {
    const LatLon p = frame.Inverse({x, y});
    lat->push_back(p.lat_deg);
    lon->push_back(p.lon_deg);
  };
  for (size_t i = 0; i < road->s.size(); ++i) {
    add(road->x[i], road->y[i], &road->centre_lat, &road->centre_lon);
    add(road->left_x[i], road->left_y[i], &road->left_lat, &road->left_lon);
    add(road->right_x[i], road->right_y[i], &road->right_lat, &road->right_lon);
  }
  road->crs_proj = frame.ProjString();
  road->crs_wkt = frame.Wkt();
  road->origin_lat_deg = frame.Origin().lat_deg;
  road->origin_lon_deg = frame.Origin().lon_deg;
}

void AddPointResiduals(const FitSummary& summary, RoadArtefact* road) {
  for (const PointResidual& r : summary.residuals) {
    road->point_line.push_back(r.line);
    road->point_side.push_back(static_cast<int64_t>(r.side));
    road->point_s.push_back(r.s_m);
    road->point_lateral.push_back(r.lateral_m);
    road->point_vertical.push_back(r.vertical_m);
    road->point_along.push_back(r.along_m);
  }
}

std::string Place(const RoadArtefact& road, size_t i) {
  char text[128];
  if (road.centre_lat.empty())
    std::snprintf(text, sizeof text, "at s = %.0f m (x %.1f, y %.1f)", road.s[i], road.x[i], road.y[i]);
  else
    std::snprintf(text, sizeof text, "at s = %.0f m (%.5f, %.5f)", road.s[i], road.centre_lat[i], road.centre_lon[i]);
  return text;
}

}  // namespace

RoadArtefact MakeRoadArtefact(const RoadInput& input, const RoadProfile& profile, const FitOptions& options,
                              const FitSummary& summary) {
  RoadArtefact road;
  road.s = profile.s;
  road.x = profile.x;
  road.y = profile.y;
  road.z = profile.z;
  road.theta = profile.theta;
  road.sigma = profile.sigma;
  road.width = profile.width;
  road.banking = profile.banking;
  road.kappa = profile.kappa;
  road.nu = profile.nu;
  road.tau = profile.tau;
  for (size_t i = 0; i < profile.s.size(); ++i) {  // eq. 7: borders at +- r_w/2 across the road
    const double half = 0.5 * profile.width[i];
    double l[3];
    LeftAcross(profile.theta[i], profile.sigma[i], profile.banking[i], l);
    road.left_x.push_back(profile.x[i] + half * l[0]);
    road.left_y.push_back(profile.y[i] + half * l[1]);
    road.right_x.push_back(profile.x[i] - half * l[0]);
    road.right_y.push_back(profile.y[i] - half * l[1]);
  }
  if (input.frame) AddGeographic(*input.frame, &road);
  AddPointResiduals(summary, &road);
  road.closed = profile.closed;
  road.length_m = profile.length();
  road.ds_m = profile.ds_m;
  road.rms_distance_m = summary.rms_distance_m;
  road.max_distance_m = summary.max_distance_m;
  road.max_distance_line = summary.max_distance_line;
  road.max_defect_position_m = summary.max_defect_position_m;
  road.max_defect_angle_rad = summary.max_defect_angle_rad;
  road.input_file = input.file;
  road.input_sha256 = FileSha256(input.file);
  road.input_format = input.format;
  road.tool_version = TTZ_VERSION;
  road.smoothing_weight = options.smoothing_weight;
  road.converged = summary.converged;
  road.iterations = summary.iterations;
  road.solve_seconds = summary.solve_seconds;
  return road;
}

namespace {

// "none (level across)", or the largest banking [deg], which border is the higher and where.
std::string BankingText(const RoadArtefact& road, size_t i) {
  if (road.banking[i] == 0.0) return "none (level across)";
  char text[160];
  std::snprintf(text, sizeof text, "%.1f deg (%s border higher) %s", std::abs(road.banking[i]) * 180.0 / M_PI,
                road.banking[i] > 0 ? "left" : "right", Place(road, i).c_str());
  return text;
}

}  // namespace

std::string FitReport(const RoadArtefact& road) {
  size_t steepest = 0, tightest = 0, banked = 0;
  for (size_t i = 0; i < road.s.size(); ++i) {
    if (std::abs(road.sigma[i]) > std::abs(road.sigma[steepest])) steepest = i;
    if (std::abs(road.kappa[i]) > std::abs(road.kappa[tightest])) tightest = i;
    if (std::abs(road.banking[i]) > std::abs(road.banking[banked])) banked = i;
  }
  double zmin = road.z[0], zmax = road.z[0];
  for (double z : road.z) zmin = std::min(zmin, z), zmax = std::max(zmax, z);
  char text[1024];
  std::snprintf(text, sizeof text,
                "length           %.1f m (%s)\n"
                "points           %zu, distance to the fitted ribbon rms %.3f m, max %.3f m (input line %lld)\n"
                "elevation        %.1f to %.1f m (range %.1f m)\n"
                "steepest slope   %.1f %% (%s) %s\n"
                "tightest radius  %.1f m (%s) %s\n"
                "largest banking  %s\n"
                "largest defect   %.2e m, %.2e rad\n"
                "solver           %s, %lld iterations, %.2f s\n",
                road.length_m, road.closed ? "closed" : "open", road.point_s.size(), road.rms_distance_m,
                road.max_distance_m, static_cast<long long>(road.max_distance_line), zmin, zmax, zmax - zmin,
                100 * std::tan(road.sigma[steepest]), road.sigma[steepest] > 0 ? "uphill" : "downhill",
                Place(road, steepest).c_str(), 1.0 / std::abs(road.kappa[tightest]),
                road.kappa[tightest] > 0 ? "left" : "right", Place(road, tightest).c_str(),
                BankingText(road, banked).c_str(), road.max_defect_position_m,
                road.max_defect_angle_rad, road.converged ? "converged" : "NOT CONVERGED",
                static_cast<long long>(road.iterations), road.solve_seconds);
  return text;
}

}  // namespace ttz::road
