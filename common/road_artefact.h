// road.h5: the fitted road on a uniform arc-length grid (schema "ttz.road", version 2; version 1,
// which had no banking, is read as a road level across).
//
// Written by road_fit, read by lap. Every dataset, unit and sign convention is documented in
// docs/road_h5.md; this struct is its in-memory form.
#pragma once

#include <string>
#include <vector>

namespace ttz {

inline constexpr const char* kRoadSchema = "ttz.road";
inline constexpr int kRoadSchemaVersion = 2;
inline constexpr int kRoadOldestSchemaVersion = 1;  // no `banking` dataset: read as zero

struct RoadArtefact {
  // Along the centre line, uniform in s.
  std::vector<double> s;      // curvilinear abscissa [m], 0 at the start
  std::vector<double> x, y;   // local frame: east, north of the frame origin [m]
  std::vector<double> z;      // elevation [m]
  std::vector<double> theta;  // heading from east, counter-clockwise [rad] (continuous, unwrapped)
  std::vector<double> sigma;  // slope [rad], positive uphill (dz/ds = sin sigma)
  std::vector<double> banking;  // xi of eq. 2 [rad], positive when the left border is the higher
  std::vector<double> width;  // r_w, border to border [m]
  // The road frame's angular velocity per metre (forward, left, up) = (tau, -nu, kappa), eq. 12:
  std::vector<double> kappa;  // cos(xi) cos(sigma) dtheta/ds + sin(xi) dsigma/ds [1/m], positive turning left
  std::vector<double> nu;     // cos(xi) dsigma/ds - sin(xi) cos(sigma) dtheta/ds [1/m]
  std::vector<double> tau;    // sin(sigma) dtheta/ds + dxi/ds [1/m]
  // Geographic coordinates (empty when the input was in local metres).
  std::vector<double> centre_lat, centre_lon, left_lat, left_lon, right_lat, right_lon;  // [deg]
  std::vector<double> left_x, left_y, right_x, right_y;  // borders in the local frame [m]

  // Per input point: where it projects and how far it is from the fitted ribbon.
  std::vector<int64_t> point_line;   // 1-based line of the input file
  std::vector<int64_t> point_side;   // 0 left border, 1 right border, 2 centre line
  std::vector<double> point_s;       // [m]
  std::vector<double> point_lateral, point_vertical, point_along;  // signed distances [m]

  // Attributes.
  bool closed = false;
  double length_m = 0.0;
  double ds_m = 0.0;
  std::string crs_proj;  // PROJ string of the local frame, "" for local inputs
  std::string crs_wkt;
  double origin_lat_deg = 0.0, origin_lon_deg = 0.0;
  double rms_distance_m = 0.0, max_distance_m = 0.0;
  int64_t max_distance_line = 0;
  double max_defect_position_m = 0.0, max_defect_angle_rad = 0.0;
  std::string input_file, input_sha256, input_format;
  std::string tool_version;
  double smoothing_weight = 0.0;
  bool converged = false;
  int64_t iterations = 0;
  double solve_seconds = 0.0;
};

// Writes atomically (temporary file, then rename). Throws InputError if `path` cannot be written.
void WriteRoad(const std::string& path, const RoadArtefact& road);

// Reads and checks schema, version, units and that all along-s datasets have the same length with
// s strictly increasing (CheckAlongS). Throws InputError naming the file and what is wrong.
RoadArtefact ReadRoad(const std::string& path);

// Throws InputError naming `where` unless s has at least 2 samples, every along-s dataset named in
// `names` (road.h5's names: "kappa", "banking", ...; all of them when empty) has as many, and s
// strictly increases. ReadRoad checks a file with it, lap's RoadTrack the channels it samples.
void CheckAlongS(const RoadArtefact& road, const std::string& where, const std::vector<std::string>& names = {});

}  // namespace ttz
