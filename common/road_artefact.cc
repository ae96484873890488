#include "common/road_artefact.h"

#include <algorithm>
#include <cstdint>

#include "common/artefact.h"
#include "common/error.h"

namespace ttz {
namespace {

using DoubleChannel = std::vector<double> RoadArtefact::*;

struct ChannelSpec {
  const char* name;
  DoubleChannel member;
  const char* units;
  const char* description;
};

// The along-s channels every road has.
const ChannelSpec kAlongS[] = {
    {"s", &RoadArtefact::s, "m", "curvilinear abscissa of the centre line, 0 at the start"},
    {"x", &RoadArtefact::x, "m", "centre line, east of the local frame origin"},
    {"y", &RoadArtefact::y, "m", "centre line, north of the local frame origin"},
    {"z", &RoadArtefact::z, "m", "centre line elevation"},
    {"theta", &RoadArtefact::theta, "rad", "heading from east, counter-clockwise, unwrapped"},
    {"sigma", &RoadArtefact::sigma, "rad", "slope, positive uphill: dz/ds = sin(sigma)"},
    {"banking", &RoadArtefact::banking, "rad", "banking xi (eq. 2), positive when the left border is the higher"},
    {"width", &RoadArtefact::width, "m", "road width r_w, border to border"},
    {"kappa", &RoadArtefact::kappa, "1/m",
     "in-plane curvature cos(xi) cos(sigma) dtheta/ds + sin(xi) dsigma/ds, positive turning left (eq. 12)"},
    {"nu", &RoadArtefact::nu, "1/m",
     "normal curvature cos(xi) dsigma/ds - sin(xi) cos(sigma) dtheta/ds, positive in a dip (eq. 12)"},
    {"tau", &RoadArtefact::tau, "1/m", "torsion sin(sigma) dtheta/ds + dxi/ds (eq. 12)"},
    {"left/x", &RoadArtefact::left_x, "m", "left border, east"},
    {"left/y", &RoadArtefact::left_y, "m", "left border, north"},
    {"right/x", &RoadArtefact::right_x, "m", "right border, east"},
    {"right/y", &RoadArtefact::right_y, "m", "right border, north"},
};

// Present only when the input was geographic.
const ChannelSpec kGeographic[] = {
    {"centre/lat", &RoadArtefact::centre_lat, "deg", "centre line latitude, WGS84"},
    {"centre/lon", &RoadArtefact::centre_lon, "deg", "centre line longitude, WGS84"},
    {"left/lat", &RoadArtefact::left_lat, "deg", "left border latitude, WGS84"},
    {"left/lon", &RoadArtefact::left_lon, "deg", "left border longitude, WGS84"},
    {"right/lat", &RoadArtefact::right_lat, "deg", "right border latitude, WGS84"},
    {"right/lon", &RoadArtefact::right_lon, "deg", "right border longitude, WGS84"},
};

const ChannelSpec kPoints[] = {
    {"points/s", &RoadArtefact::point_s, "m", "abscissa of each input point's projection on the ribbon"},
    {"points/lateral", &RoadArtefact::point_lateral, "m",
     "input point minus fitted border (or centre) across the road, positive to the left"},
    {"points/vertical", &RoadArtefact::point_vertical, "m", "input point minus fitted elevation"},
    {"points/along", &RoadArtefact::point_along, "m", "input point ahead of its projection along the road"},
};

}  // namespace

void WriteRoad(const std::string& path, const RoadArtefact& road) {
  ArtefactWriter w(path, kRoadSchema, kRoadSchemaVersion);
  for (const auto& c : kAlongS) w.WriteVector(c.name, road.*c.member, c.units, c.description);
  if (!road.centre_lat.empty())
    for (const auto& c : kGeographic) w.WriteVector(c.name, road.*c.member, c.units, c.description);
  for (const auto& c : kPoints) w.WriteVector(c.name, road.*c.member, c.units, c.description);
  w.WriteIntVector("points/line", road.point_line, "1", "line of the input file (1-based)");
  w.WriteIntVector("points/side", road.point_side, "1", "0 left border, 1 right border, 2 centre line");
  w.WriteBoolAttribute("closed", road.closed);
  w.WriteAttribute("length_m", road.length_m);
  w.WriteAttribute("ds_m", road.ds_m);
  w.WriteAttribute("crs_proj", road.crs_proj);
  w.WriteAttribute("crs_wkt", road.crs_wkt);
  w.WriteAttribute("origin_lat_deg", road.origin_lat_deg);
  w.WriteAttribute("origin_lon_deg", road.origin_lon_deg);
  w.WriteAttribute("rms_distance_m", road.rms_distance_m);
  w.WriteAttribute("max_distance_m", road.max_distance_m);
  w.WriteAttribute("max_distance_line", road.max_distance_line);
  w.WriteAttribute("max_defect_position_m", road.max_defect_position_m);
  w.WriteAttribute("max_defect_angle_rad", road.max_defect_angle_rad);
  w.WriteAttribute("input_file", road.input_file);
  w.WriteAttribute("input_sha256", road.input_sha256);
  w.WriteAttribute("input_format", road.input_format);
  w.WriteAttribute("tool_version", road.tool_version);
  w.WriteAttribute("smoothing_weight", road.smoothing_weight);
  w.WriteBoolAttribute("converged", road.converged);
  w.WriteAttribute("iterations", road.iterations);
  w.WriteAttribute("solve_seconds", road.solve_seconds);
  w.Commit();
}

void CheckAlongS(const RoadArtefact& road, const std::string& where, const std::vector<std::string>& names) {
  const size_t n = road.s.size();
  if (n < 2) throw InputError(where, "dataset 's' has " + std::to_string(n) + " samples, at least 2 expected");
  for (const auto& c : kAlongS) {
    if (!names.empty() && std::find(names.begin(), names.end(), c.name) == names.end()) continue;
    if ((road.*c.member).size() != n)
      throw InputError(where, std::string("dataset '") + c.name + "' has " + std::to_string((road.*c.member).size()) +
                                  " samples, " + std::to_string(n) + " expected (as 's')");
  }
  for (size_t i = 1; i < n; ++i)
    if (!(road.s[i] > road.s[i - 1]))
      throw InputError(where, "dataset 's' is not strictly increasing at index " + std::to_string(i));
}

RoadArtefact ReadRoad(const std::string& path) {
  ArtefactReader r(path, kRoadSchema, kRoadSchemaVersion, kRoadOldestSchemaVersion);
  RoadArtefact road;
  for (const auto& c : kAlongS)
    if (c.member != &RoadArtefact::banking || r.schema_version() > 1) road.*c.member = r.ReadVector(c.name, c.units);
  if (r.schema_version() == 1) road.banking.assign(road.s.size(), 0.0);  // version 1: no banking
  if (r.HasDataset("centre/lat"))
    for (const auto& c : kGeographic) road.*c.member = r.ReadVector(c.name, c.units);
  for (const auto& c : kPoints) road.*c.member = r.ReadVector(c.name, c.units);
  road.point_line = r.ReadIntVector("points/line", "1");
  road.point_side = r.ReadIntVector("points/side", "1");
  CheckAlongS(road, path);
  road.closed = r.ReadBoolAttribute("closed");
  road.length_m = r.ReadDoubleAttribute("length_m");
  road.ds_m = r.ReadDoubleAttribute("ds_m");
  road.crs_proj = r.ReadStringAttribute("crs_proj");
  road.crs_wkt = r.ReadStringAttribute("crs_wkt");
  road.origin_lat_deg = r.ReadDoubleAttribute("origin_lat_deg");
  road.origin_lon_deg = r.ReadDoubleAttribute("origin_lon_deg");
  road.rms_distance_m = r.ReadDoubleAttribute("rms_distance_m");
  road.max_distance_m = r.ReadDoubleAttribute("max_distance_m");
  road.max_distance_line = r.ReadIntAttribute("max_distance_line");
  road.max_defect_position_m = r.ReadDoubleAttribute("max_defect_position_m");
  road.max_defect_angle_rad = r.ReadDoubleAttribute("max_defect_angle_rad");
  road.input_file = r.ReadStringAttribute("input_file");
  road.input_sha256 = r.ReadStringAttribute("input_sha256");
  road.input_format = r.ReadStringAttribute("input_format");
  road.tool_version = r.ReadStringAttribute("tool_version");
  road.smoothing_weight = r.ReadDoubleAttribute("smoothing_weight");
  road.converged = r.ReadBoolAttribute("converged");
  road.iterations = r.ReadIntAttribute("iterations");
  road.solve_seconds = r.ReadDoubleAttribute("solve_seconds");
  return road;
}

}  // namespace ttz
