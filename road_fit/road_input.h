// Reading the measured road: border points, border pairs, centre lines, GDAL line layers.
//
// Every accepted form and column name is listed in docs/road_fit.md. All forms become a list of
// observations in one local metric frame (x east, y north, z up, metres).
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/geodesy.h"

namespace ttz::road {

enum class Side { kLeft = 0, kRight = 1, kCentre = 2 };

// One measured point of the road in the local frame.
struct Observation {
  Side side = Side::kCentre;
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  // Road width at this point [m]; set on centre observations only (from the file or --width).
  double width_m = std::numeric_limits<double>::quiet_NaN();
  // Banking xi at this point [rad], positive when the left border is the higher (road_fit/ribbon.h);
  // centre observations of inputs with a banking column only, NaN otherwise.
  double banking_rad = std::numeric_limits<double>::quiet_NaN();
  long line = 0;  // 1-based line (or feature vertex index for GDAL layers) of the input it came from
};

struct RoadInput {
  std::string file;
  std::string format;  // "border-points", "border-pairs", "centre-line", "gdal-line"
  // Left and right border points (border forms) or centre points (centre forms), each side in
  // order along the road, in input order.
  std::vector<Observation> points;
  // Set when the input was geographic (lat/lon): the local frame the points are expressed in.
  std::optional<LocalFrame> frame;
  bool has_elevation = false;  // false: z_m is 0 (flat road, a warning was logged)
  // The input says how the road is banked: a banking column, or border points with their own
  // elevations (not attached from --elevation, whose models are too coarse across a road).
  bool carries_banking = false;
};

struct ReadOptions {
  // Raster (any format GDAL reads; sampled bilinearly) or polyline CSV "lat,lon,elevation" giving
  // the elevation of points that have none. Empty: none.
  std::string elevation_source;
  // Width [m] for centre lines that carry none. NaN: none (then such an input is an error).
  double width_m = std::numeric_limits<double>::quiet_NaN();
  // When true, isolated far outliers ("spikes") are kept with a warning (the fit's robust loss
  // absorbs them); otherwise they are an InputError naming the line.
  bool robust = false;
};

// Reads and validates `path`, detecting its form by extension and header. Throws InputError with
// file, line/column and what was expected on any defect (see docs/road_fit.md).
RoadInput ReadRoadInput(const std::string& path, const ReadOptions& options);

}  // namespace ttz::road
