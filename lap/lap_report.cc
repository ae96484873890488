#include "lap/lap_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <sstream>

namespace ttz::lap {
namespace {

constexpr double kKmH = 3.6;  // (km/h) / (m/s)

std::string Printf(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string JsonNumber(double x) { return std::isfinite(x) ? Printf("%.10g", x) : "null"; }

std::string JsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04x", c);
      out += u;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// "lap time differs by X %, states by Y % (STATE at s = S m)", the state and place of the largest
// difference, or why there is no re-simulated lap time.
std::string ResimLine(const ResimReport& r) {
  if (!std::isfinite(r.lap_time)) return "no lap time (" + r.message + ")";
  return Printf("lap time differs by %.3g %%, ", 100.0 * r.lap_time_relative) +
         Printf("states by %.3g %% (", 100.0 * r.max_state_difference_all) + kStateNames[r.worst_state] +
         Printf(" at s = %.0f m", r.worst_s) + (r.passed ? ")" : "; failed)");
}

// The largest finite sensitivities of design values by size, one per line: "key  +0.123 s".
std::string SensitivityLines(const std::vector<DesignSensitivity>& sensitivities) {
  std::vector<DesignSensitivity> largest;
  std::copy_if(sensitivities.begin(), sensitivities.end(), std::back_inserter(largest),
               [](const DesignSensitivity& d) { return d.kind == "design" && std::isfinite(d.per_percent); });
  const size_t shown = std::min<size_t>(largest.size(), kReportedSensitivities);
  std::partial_sort(largest.begin(), largest.begin() + shown, largest.end(),
                    [](const DesignSensitivity& a, const DesignSensitivity& b) {
                      return std::abs(a.per_percent) > std::abs(b.per_percent);
                    });
  std::string lines =
      "sensitivity    lap time per 1 % more of (the largest design values; all in lap.h5 sensitivity/*):\n";
  for (size_t i = 0; i < shown; ++i) {
    char line[160];
    std::snprintf(line, sizeof line, "               %-48s %+.3f s\n", largest[i].key.c_str(), largest[i].per_percent);
    lines += line;
  }
  return lines;
}

}  // namespace

std::string FormatLapTime(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "-:--.-";
  const long long tenths = std::llround(seconds * 10.0);
  char text[32];
  std::snprintf(text, sizeof text, "%lld:%02lld.%lld", tenths / 600, tenths % 600 / 10, tenths % 10);
  return text;
}

std::string LapReportText(const LapSolution& sol, const SolveSummary& summary, const LapFigures& f,
                          const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities) {
  std::ostringstream o;
  // A solve that stopped leaves its last point, whose figures need not be a lap's (a negative
  // energy after one iteration): said before them, not only in the line at the end.
  if (!summary.converged) o << "NOT CONVERGED: the figures below are of the solver's last point, not of a lap\n";
  o << "lap time       " << FormatLapTime(f.lap_time) << Printf("  (%.3f s; ", f.lap_time)
    << Printf("extrapolated to no barrier: %.3f s)\n", sol.lap_time_extrapolated);
  o << "average speed  " << Printf("%.1f km/h\n", f.average_speed * kKmH);
  o << "energy used    " << Printf("%.2f MJ", f.energy_used * 1e-6)
    << Printf(" (%.1f %% of the pack)\n", 100.0 * f.energy_fraction);
  o << "top speed      " << Printf("%.1f km/h\n", f.top_speed * kKmH);
  o << "start speed    " << Printf("%.1f km/h\n", f.start_speed * kKmH);
  o << "re-simulation  " << ResimLine(resim) << "\n";
  o << "converged      " << (summary.converged ? "yes" : "no (" + SolveMessage(summary) + ")") << "\n";
  if (!sensitivities.empty()) o << SensitivityLines(sensitivities);
  return o.str();
}

std::string LapReportJson(const LapSolution& sol, const SolveSummary& summary, const LapFigures& f,
                          const ResimReport& resim, const std::vector<DesignSensitivity>& sensitivities) {
  std::ostringstream o;
  o << "{\"lap_time\": " << JsonNumber(f.lap_time)
    << ", \"lap_time_text\": " << JsonString(FormatLapTime(f.lap_time))
    << ", \"lap_time_extrapolated\": " << JsonNumber(sol.lap_time_extrapolated)
    << ", \"eps\": " << JsonNumber(sol.eps)
    << ", \"average_speed\": " << JsonNumber(f.average_speed)
    << ", \"energy_used\": " << JsonNumber(f.energy_used)
    << ", \"energy_fraction\": " << JsonNumber(f.energy_fraction)
    << ", \"top_speed\": " << JsonNumber(f.top_speed)
    << ", \"start_speed\": " << JsonNumber(f.start_speed)
    << ", \"converged\": " << (summary.converged ? "true" : "false")
    << ", \"message\": " << JsonString(SolveMessage(summary))
    << ", \"max_residual\": " << JsonNumber(summary.max_residual)
    << ", \"max_state_defect\": " << JsonNumber(summary.max_state_defect)
    << ", \"resim_lap_time\": " << JsonNumber(resim.lap_time)
    << ", \"resim_lap_time_difference\": " << JsonNumber(resim.lap_time_difference)
    << ", \"resim_lap_time_relative\": " << JsonNumber(resim.lap_time_relative)
    << ", \"resim_max_state_difference\": " << JsonNumber(resim.max_state_difference_all)
    << ", \"resim_worst_state\": " << JsonString(kStateNames[resim.worst_state])
    << ", \"resim_worst_s\": " << JsonNumber(resim.worst_s)
    << ", \"resim_passed\": " << (resim.passed ? "true" : "false")
    << ", \"iterations\": " << summary.iterations
    << ", \"solve_seconds\": " << JsonNumber(summary.solve_seconds)
    << ", \"nodes\": " << sol.s.size() << ", \"sensitivity_per_percent\": {";
  for (size_t i = 0; i < sensitivities.size(); ++i)
    o << (i > 0 ? ", " : "") << JsonString(sensitivities[i].key) << ": " << JsonNumber(sensitivities[i].per_percent);
  o << "}, \"sensitivity_kind\": {";
  for (size_t i = 0; i < sensitivities.size(); ++i)
    o << (i > 0 ? ", " : "") << JsonString(sensitivities[i].key) << ": " << JsonString(sensitivities[i].kind);
  o << "}}\n";
  return o.str();
}

}  // namespace ttz::lap
