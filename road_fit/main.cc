// road_fit: measured road borders (or a centre line) -> a smooth 3-D ribbon in road.h5.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "common/artefact.h"
#include "common/command_line.h"
#include "common/error.h"
#include "common/log.h"
#include "common/memory.h"
#include "common/road_artefact.h"
#include "road_fit/ribbon_fit.h"
#include "road_fit/road_input.h"
#include "road_fit/road_output.h"
#include "road_fit/road_profile.h"

namespace {

struct Arguments {
  std::string input, output;
  ttz::road::ReadOptions read;
  ttz::road::FitOptions fit;
  bool closed = false, open = false, quiet = false;
};

void DefineOptions(CLI::App& app, Arguments& a) {
  app.add_option("INPUT", a.input,
                 "border points (side,lat,lon[,elevation]), border pairs in metres, a centre line with width, "
                 "or a GDAL line layer (see docs/road_fit_inputs.md)")
      ->required();
  app.add_option("-o,--output", a.output, "road artefact to write (HDF5, see docs/road_h5.md)")->required();
  app.add_option("--ds", a.fit.ds_m, "node and output spacing along the road [m]")
      ->check(ttz::kPositiveNumber)
      ->capture_default_str();
  app.add_option("--smoothing", a.fit.smoothing_weight,
                 "weight w_u of the smoothness term U(u) (eq. 4a); larger is smoother")
      ->check(ttz::kPositiveNumber)
      ->capture_default_str();
  auto* closed = app.add_flag("--closed", a.closed, "the road is a closed circuit (default: detected)");
  app.add_flag("--open", a.open, "the road is not a circuit (default: detected)")->excludes(closed);
  app.add_option("--elevation", a.read.elevation_source,
                 "elevation for points without it: a raster GDAL reads, or a polyline CSV lat,lon,elevation");
  app.add_option("--width", a.read.width_m, "road width [m] for centre lines without a width column")
      ->check(ttz::kPositiveNumber);
  app.add_flag("--level", a.fit.level,
               "fit the road level across (banking 0, as the paper) even when the input gives its banking");
  app.add_flag("--robust", a.fit.robust,
               "keep far outliers and absorb them with a Cauchy loss instead of rejecting the input");
  app.add_flag("-q,--quiet", a.quiet, "print warnings and errors only");
}

int Run(const Arguments& a) {
  ttz::road::ReadOptions read = a.read;
  read.robust = a.fit.robust;
  ttz::road::FitOptions fit = a.fit;
  fit.topology = a.closed ? ttz::road::Topology::kClosed
                          : a.open ? ttz::road::Topology::kOpen : ttz::road::Topology::kAuto;
  ttz::CheckOutputFolder(a.output);
  const ttz::road::RoadInput input = ttz::road::ReadRoadInput(a.input, read);
  ttz::road::FitSummary summary;
  const ttz::road::Ribbon ribbon = ttz::road::FitRibbon(input, fit, &summary);
  // After the fit, so that an input the fit refuses gets its one line alone.
  if (input.carries_banking && !fit.level && input.format != "centre-line")
    ttz::Log(ttz::LogKind::kInfo, a.input + ": the banking is fitted from the borders' elevations; give --level "
                                            "if they come from an elevation model (docs/road_fit_inputs.md)");
  const ttz::RoadArtefact road =
      ttz::road::MakeRoadArtefact(input, ttz::road::SampleRibbon(ribbon, fit.ds_m), fit, summary);
  ttz::WriteRoad(a.output, road);
  std::cout << ttz::road::FitReport(road) << std::flush;
  if (!road.converged) {
    ttz::Log(ttz::LogKind::kError, "the fit did not converge (" + summary.termination + "); " + a.output +
                                       " is written with converged = false");
    return ttz::kExitNotConverged;
  }
  return ttz::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  ttz::KeepFreedMemory();
  CLI::App app{"road_fit: fit a smooth 3-D road ribbon (paper eq. 4-8) to measured border points"};
  Arguments arguments;
  DefineOptions(app, arguments);
  return ttz::RunCommandLine("road_fit", app, argc, argv, [&] {
    if (arguments.quiet) ttz::SetLogLevel(1);
    return Run(arguments);
  });
}
