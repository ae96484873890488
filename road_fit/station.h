// Where a measured point sits along the ribbon: the interval and fraction of its projection on
// the centre polyline of the nodes (the estimate zeta_i of the paper's section 2.1).
#pragma once

#include <array>
#include <vector>

#include "road_fit/ribbon_fit.h"

namespace ttz::road {

struct Station {
  int interval = 0;       // vertex k of the segment [k, k+1]
  double t = 0.0;         // fraction in [0, 1] along it
  double distance_m = 0;  // horizontal distance of the point to the centre polyline
};

using PointXY = std::array<double, 2>;

// Projects points, in their order along the road, onto a polyline in the x-y plane: the first by
// a global search, the next ones in a window ahead of the previous match (so that a road passing
// near itself does not make a point jump to the wrong stretch). A closed polyline's last vertex
// joins its first. Returns one station per point, in the same order.
std::vector<Station> ProjectOntoPolyline(const std::vector<PointXY>& vertices, bool closed,
                                         const std::vector<PointXY>& points);

// The same onto the ribbon's node polyline, for one side's observations.
std::vector<Station> ProjectOntoRibbon(const Ribbon& ribbon, const std::vector<Observation>& points);

}  // namespace ttz::road
