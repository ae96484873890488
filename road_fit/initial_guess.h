// A first ribbon from the measured points: a rough centre polyline, resampled and smoothed, whose
// headings, slopes and their rates start the least-squares fit (eq. 4-8).
#pragma once

#include <array>
#include <vector>

#include "road_fit/ribbon_fit.h"
#include "road_fit/road_input.h"

namespace ttz::road {

// A 3-D polyline with a width at each vertex.
struct CentrePolyline {
  std::vector<std::array<double, 3>> p;
  std::vector<double> width_m;
};

// Border forms: the midpoint of each left point and its nearest point on the right border, with
// their distance as width. Centre forms: the centre points and their widths. Points flagged as
// spikes (far from both neighbours) are left out.
CentrePolyline RoughCentre(const RoadInput& input);

// Horizontal distance between the polyline's last and first points [m].
double EndsGap(const CentrePolyline& centre);

// Nodes every ~ds metres of the polyline's arc length (zeta), states from smoothed finite
// differences, controls from the differences of the states; s = zeta.
Ribbon InitialRibbon(const CentrePolyline& centre, double ds_m, bool closed);

}  // namespace ttz::road
