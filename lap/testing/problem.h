// The problem most lap tests start from: data/bx15.yaml's bike, a road on a uniform mesh, and the
// quasi-steady lap on that mesh (the solvers' guess, lap/qss.h). Tests only: TTZ_SOURCE_DIR is a
// compile definition of the test targets (CMakeLists.txt, ttz_add_test).
#pragma once

#include <string>
#include <vector>

#include "common/road_artefact.h"
#include "lap/bike.h"
#include "lap/mesh.h"
#include "lap/qss.h"
#include "lap/road_track.h"

namespace ttz::lap::testing {

// The lap tests' bike: the reference bike, data/bx15.yaml, with the motor voltage limit it had
// until session 20 (90 V, kTestVoltageMax) and then `overrides` as `--set` gives them
// ("key.path=value"). The tests' saved reference solutions (lap times, iteration counts) were
// measured with 90 V; at the reference's 80 V (docs/bike.md) their uncalibrated 600 A bike rides
// the voltage limit on fast roads, and the indirect solver fails two of them (the 5 km mixed road,
// the windowed first step: docs/lap.md "Status").
inline constexpr const char* kTestVoltageMax = "motor.voltage_max_v=90";
inline Vehicle Bx15(const std::vector<std::string>& overrides = {}) {
  std::vector<std::string> all{kTestVoltageMax};
  all.insert(all.end(), overrides.begin(), overrides.end());
  return MakeVehicle(LoadBike(std::string(TTZ_SOURCE_DIR) + "/data/bx15.yaml", all));
}

// `road` on a uniform mesh of `ds_m` metres and the QSS lap of bike `v` on it. Change the bike
// (its start state, V0, ...) before building this: the QSS starts from it.
struct MeshedRoad {
  MeshedRoad(const Vehicle& v, const RoadArtefact& r, double ds_m)
      : road(r), mesh(UniformMesh(road.Length(), ds_m)), qss(ComputeQss(v, road, mesh)) {}
  RoadTrack road;
  std::vector<double> mesh;  // node abscissae [m]
  QssLap qss;                // the quasi-steady lap on `mesh`, the solvers' guess
};

}  // namespace ttz::lap::testing
