// Synthetic roads with known analytic geometry, for tests: the truth densely sampled, and measured
// border points drawn from it with irregular spacing and Gaussian noise.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "road_fit/road_input.h"

namespace ttz::testing {

struct RoadSpec {
  std::string name;
  double length_m = 0.0;
  bool closed = false;
  std::function<double(double)> heading_rate;  // dtheta/ds [1/m] at s
  std::function<double(double)> slope;         // sigma [rad] at s, positive uphill
  std::function<double(double)> width;         // [m] at s
  std::function<double(double)> banking = [](double) { return 0.0; };  // xi [rad] at s, left higher positive
};

// A 1 km climbing curve whose curvature varies smoothly (radius 55 to 500 m) and whose slope
// varies from 3 to 7 %, width 6 to 8 m.
RoadSpec ClimbingCurve();
// An S-bend of clothoids: straight, clothoid into a 40 m radius left, arc, clothoid through zero
// to a 40 m radius right, arc, clothoid out, straight; climbing at 6 %; width 6 m.
RoadSpec ClothoidSBend();
// A flat circle of radius 100 m, closed, width 8 m.
RoadSpec Circle();
// The climbing curve banked as a speedway is, the outer (right) border higher, by up to 9 degrees
// where the curve is tightest.
RoadSpec BankedClimbingCurve();

// The truth every `step` metres: exact integration of theta' and sigma (RK4); kappa is the road
// frame's in-plane curvature of eq. 12 (road_fit/ribbon.h).
struct TrueRoad {
  std::vector<double> s, x, y, z, theta, sigma, kappa, width, banking;
  bool closed = false;
  double length() const { return s.back(); }
  // Index of the sample nearest to (x, y) in the plane.
  size_t Nearest(double px, double py) const;
};
TrueRoad Integrate(const RoadSpec& spec, double step_m = 0.05);

struct SamplingOptions {
  double min_spacing_m = 2.0;   // spacing of border points along each side, uniform in [min, max]
  double max_spacing_m = 8.0;
  double noise_sd_m = 0.3;      // Gaussian noise on x, y and z of every point
  unsigned seed = 1;
};

// Left and right border points (the paper's input form) in local metres.
road::RoadInput SampleBorders(const TrueRoad& road, const SamplingOptions& options);

}  // namespace ttz::testing
