// The arc-length mesh s_0 = 0 < ... < s_N = length on which both solvers transcribe the problem
// (eq. 37-38, lap/solver/transcription.h).
//
// Why not only uniform: an interval's length in time, h_k / V, is what the transcription has to
// resolve, and the bike's speed along a lap spans 5 m/s at the launch to 60 m/s. Measured on the
// first 2 km of the TT course with Ipopt (10 m mesh): the uniform mesh's first interval lasts ~2 s
// of the launch from 5 m/s, the tyre's slip (beta) there cannot follow, and the re-simulation
// check (lap/resimulate.h) diverges at s = 10 m; limiting every interval to 0.25 s of the
// quasi-steady lap (QSS, lap/qss.h) refines the launch to 1.25 m, 201 -> 256 nodes, and the
// launch re-simulates (docs/lap.md, "Mesh").
#pragma once

#include <vector>

#include "lap/model/vehicle.h"
#include "lap/qss.h"
#include "lap/road_track.h"

namespace ttz::lap {

struct MeshOptions {
  double ds_m = 1.0;        // largest spacing [m] (--ds)
  // Largest duration of an interval at the QSS speed [s] (--dt-max); 0 keeps the mesh uniform.
  // 0.25 s is the roll mode's time constant (lap/resimulate.h); it refines only where the QSS
  // speed is below ds_m / dt_max_s: the launch and slow bends at a 10 m mesh; at the default 1 m mesh
  // only below 4 m/s, slower than the launch at 5 m/s.
  double dt_max_s = 0.25;
};

// Nodes 0 = s_0 < ... < s_N = length, equally spaced, spacing at most `ds` [m].
std::vector<double> UniformMesh(double length, double ds);

// The uniform mesh of `length`, with every interval shortened where needed to at most
// options.dt_max_s at the speed of `qss` (the QSS lap on any mesh of the same road; linear in s
// between its nodes, the interval's smaller end speed).
std::vector<double> TimeLimitedMesh(double length, const QssLap& qss, const MeshOptions& options);

// The mesh of `lap` on the first `length` metres of `road`: TimeLimitedMesh with the QSS lap of
// vehicle `v` on the uniform mesh (not computed when options.dt_max_s is 0).
std::vector<double> LapMesh(const Vehicle& v, const RoadTrack& road, double length, const MeshOptions& options);

}  // namespace ttz::lap
