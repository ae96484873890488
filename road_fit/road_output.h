// The fitted ribbon as a road.h5 artefact, and the statistics road_fit prints.
#pragma once

#include <string>

#include "common/road_artefact.h"
#include "road_fit/ribbon_fit.h"
#include "road_fit/road_profile.h"

namespace ttz::road {

RoadArtefact MakeRoadArtefact(const RoadInput& input, const RoadProfile& profile, const FitOptions& options,
                              const FitSummary& summary);

// Lines for stdout: length, topology, distances to the input, steepest slope, tightest radius, largest banking
// with where they are, solver figures.
std::string FitReport(const RoadArtefact& road);

}  // namespace ttz::road
