// The `lap` command's summary on stdout: a few human lines, or the same as one JSON object.
#pragma once

#include <string>
#include <vector>

#include "lap/lap_channels.h"
#include "lap/resimulate.h"
#include "lap/sensitivity.h"
#include "lap/solver/solution.h"

namespace ttz::lap {

// A time as minutes:seconds with tenths, "m:ss.s" (72.46 s -> "1:12.5").
std::string FormatLapTime(double seconds);

// Lap time, average speed [km/h], energy used [MJ] and % of the pack, top and start speed [km/h], the
// re-simulation's lap-time and largest state difference [%], converged, and the
// kReportedSensitivities largest finite sensitivities of design values (lap time per 1 % more of
// a bike value of kind "design", SensitivityKind in lap/sensitivity.h).
std::string LapReportText(const LapSolution& sol, const SolveSummary& summary, const LapFigures& f,
                          const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities);
inline constexpr int kReportedSensitivities = 5;

// The same figures as one JSON object on one line, named and in SI units as lap.h5's attributes
// (docs/lap_h5.md), every sensitivity as "sensitivity_per_percent": {key: seconds} and its kind as
// "sensitivity_kind": {key: kind}; non-finite numbers are null.
std::string LapReportJson(const LapSolution& sol, const SolveSummary& summary, const LapFigures& f,
                          const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities);

}  // namespace ttz::lap
