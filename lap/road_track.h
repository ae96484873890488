// The road as the lap solver sees it: road.h5's curvatures, slope and width as smooth functions
// of s (cubic Hermite interpolation through the samples, with derivatives), in the model's frame
// (lap/model/state.h: kappa changes sign, nu, tau, sigma and the banking xi do not).
#pragma once

#include <string>
#include <vector>

#include "common/road_artefact.h"
#include "lap/model/road_point.h"

namespace ttz::lap {

class RoadTrack {
 public:
  // Throws ttz::InputError naming `name` (the road file) unless the road has at least two
  // samples uniformly spaced in s (road_fit writes them so); s is taken relative to its first
  // sample.
  explicit RoadTrack(const RoadArtefact& road, const std::string& name = "road");

  // The road at arc length s in [0, Length()] (clamped).
  RoadPoint At(double s) const;
  double Length() const { return length_; }
  bool Closed() const { return closed_; }

 private:
  double Sample(const std::vector<double>& f, double s, double* derivative) const;
  std::vector<double> kappa_, nu_, tau_, sigma_, xi_, width_;
  double ds_ = 1.0, length_ = 0.0;
  bool closed_ = false;
};

}  // namespace ttz::lap
