// Benchmark of the road fit on the Snaefell Mountain Course: the full course and pieces of it.
// Prints wall time, Ceres iterations, time per iteration and peak memory (not a test).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/log.h"
#include "common/memory.h"
#include "road_fit/ribbon_fit.h"
#include "road_fit/road_input.h"

int main(int argc, char** argv) {
  ttz::KeepFreedMemory();  // as road_fit
  if (argc < 3) {
    std::fprintf(stderr, "usage: road_fit_bench SHARED_DATA_DIR LENGTH_KM [LENGTH_KM ...]\n");
    return 2;
  }
  ttz::SetLogLevel(1);
  const std::string data = argv[1];
  ttz::road::ReadOptions read;
  read.width_m = 7;
  read.elevation_source = data + "/snaefell/elevation-flightgear.csv";
  const ttz::road::RoadInput course = ttz::road::ReadRoadInput(data + "/snaefell/centreline-osm.csv", read);
  std::printf("%-10s %8s %8s %6s %8s %10s %10s %8s\n", "piece", "nodes", "length", "iters", "wall_s", "s_per_iter",
              "peak_MB", "rms_m");
  for (int a = 2; a < argc; ++a) {
    const double km = std::stod(argv[a]);
    ttz::road::RoadInput piece = course;
    double along = 0;
    for (size_t i = 1; i < piece.points.size(); ++i) {
      along += std::hypot(piece.points[i].x_m - piece.points[i - 1].x_m, piece.points[i].y_m - piece.points[i - 1].y_m);
      if (along > km * 1000) {
        piece.points.resize(i);
        break;
      }
    }
    ttz::road::FitOptions options;
    options.topology = piece.points.size() == course.points.size() ? ttz::road::Topology::kClosed : ttz::road::Topology::kOpen;
    ttz::road::FitSummary summary;
    const auto start = std::chrono::steady_clock::now();
    const ttz::road::Ribbon ribbon = ttz::road::FitRibbon(piece, options, &summary);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    std::printf("%-10s %8zu %8.0f %6d %8.2f %10.3f %10.0f %8.3f%s\n", (std::string(argv[a]) + " km").c_str(),
                ribbon.x.size(), ribbon.length(), summary.iterations, wall, wall / std::max(1, summary.iterations),
                usage.ru_maxrss / 1024.0, summary.rms_distance_m, summary.converged ? "" : "  NOT CONVERGED");
  }
  return 0;
}
