// The problem most lap tests start from: data/bx15.yaml's bike at 90 V and c_r = 0 (Bx15()), a
// road on a uniform mesh, and the quasi-steady lap on that mesh (the solvers' guess, lap/qss.h).
// Tests only: TTZ_SOURCE_DIR is a compile definition of the test targets (CMakeLists.txt,
// ttz_add_test).
#pragma once

#include <string>
#include <vector>

#include "common/road_artefact.h"
#include "lap/bike.h"
#include "lap/mesh.h"
#include "lap/qss.h"
#include "lap/road_track.h"
#include "lap/testing/test_bike.h"

namespace ttz::lap::testing {

// The lap tests' bike: the reference bike, data/bx15.yaml, with the motor voltage limit and the
// price on rolling of their saved reference solutions (kTestVoltageMaxSetting,
// kTestRollPriceSetting, test_bike.h), then `overrides` as `--set` gives them ("key.path=value").
inline Vehicle Bx15(const std::vector<std::string>& overrides = {}) {
  std::vector<std::string> all{kTestVoltageMaxSetting, kTestRollPriceSetting};
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
