// Internal to the road input readers: raw points as read, before the local frame and the checks.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "road_fit/road_input.h"

namespace ttz::road {

struct RawPoint {
  Side side = Side::kCentre;
  double u = 0.0;  // latitude [deg] (geographic) or x [m] (local)
  double v = 0.0;  // longitude [deg] (geographic) or y [m] (local)
  double z = std::nan("");      // elevation [m], NaN when the input has none
  double width = std::nan("");  // centre forms only [m]
  double banking = std::nan("");  // centre forms only [rad], NaN when the input has none
  long line = 0;
};

struct RawInput {
  std::string format;
  bool geographic = false;
  std::vector<RawPoint> points;
};

// CSV forms: border points (long form), border pairs, centre line (see docs/road_fit_inputs.md).
RawInput ReadCsvForms(const std::string& path);
// Any GDAL line layer: a geographic centre line.
RawInput ReadGdalLine(const std::string& path);
bool IsGdalVectorFile(const std::string& path);

// Elevation of geographic or local points from a raster or a polyline CSV lat,lon,elevation.
// Points are already in the local frame (x_m, y_m); `frame` is set for geographic inputs.
void AttachElevation(const std::string& source, const std::string& input_file, const std::optional<LocalFrame>& frame,
                     std::vector<Observation>* points);

}  // namespace ttz::road
