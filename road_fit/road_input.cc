#include "road_fit/road_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/error.h"
#include "common/log.h"
#include "road_fit/input_forms.h"

namespace ttz::road {
namespace {

constexpr size_t kMinPoints = 10;
constexpr double kDuplicateM = 1e-3;
constexpr double kMaxAbsElevationM = 9000.0;

const char* SideName(Side s) { return s == Side::kLeft ? "left" : s == Side::kRight ? "right" : "centre"; }

void CheckGeographic(const std::string& file, const RawInput& in) {
  for (const RawPoint& p : in.points) {
    if (p.u < -90 || p.u > 90)
      throw InputError(Where(file, p.line), "latitude " + std::to_string(p.u) + " outside [-90, 90]");
    if (p.v < -180 || p.v > 180)
      throw InputError(Where(file, p.line), "longitude " + std::to_string(p.v) + " outside [-180, 180]");
  }
}

std::optional<LocalFrame> FrameFor(const RawInput& in) {
  if (!in.geographic) return std::nullopt;
  double lat = 0, lon = 0;
  for (const RawPoint& p : in.points) lat += p.u, lon += p.v;
  return LocalFrame::CentredOn({lat / in.points.size(), lon / in.points.size()});
}

std::vector<Observation> ToLocal(const RawInput& in, const std::optional<LocalFrame>& frame) {
  std::vector<Observation> out;
  for (const RawPoint& p : in.points) {
    Observation o;
    o.side = p.side;
    const EastNorth xy = frame ? frame->Forward({p.u, p.v}) : EastNorth{p.u, p.v};
    o.x_m = xy.x_m;
    o.y_m = xy.y_m;
    o.z_m = std::isnan(p.z) ? 0.0 : p.z;
    o.width_m = p.width;
    o.banking_rad = p.banking;
    o.line = p.line;
    out.push_back(o);
  }
  return out;
}

// Drops consecutive duplicates of each side (with one warning).
std::vector<Observation> DropDuplicates(const std::string& file, const std::vector<Observation>& points) {
  std::vector<Observation> kept;
  long dropped = 0, first_line = 0;
  for (const Observation& o : points) {
    auto last = std::find_if(kept.rbegin(), kept.rend(), [&](const Observation& k) { return k.side == o.side; });
    if (last != kept.rend() && std::hypot(o.x_m - last->x_m, o.y_m - last->y_m) < kDuplicateM) {
      if (dropped++ == 0) first_line = o.line;
      continue;
    }
    kept.push_back(o);
  }
  if (dropped > 0)
    Log(LogKind::kWarning, Where(file, first_line) + ": " + std::to_string(dropped) +
                               " duplicate consecutive point(s) dropped (first at this line)");
  return kept;
}

std::vector<const Observation*> OfSide(const std::vector<Observation>& points, Side side) {
  std::vector<const Observation*> out;
  for (const Observation& o : points)
    if (o.side == side) out.push_back(&o);
  return out;
}

// An isolated far outlier: far from both neighbours on its side while they are close together.
void CheckSpikes(const std::string& file, const std::vector<const Observation*>& side, bool robust) {
  const auto d = [](const Observation* a, const Observation* b) { return std::hypot(a->x_m - b->x_m, a->y_m - b->y_m); };
  for (size_t i = 1; i + 1 < side.size(); ++i) {
    const double d_prev = d(side[i - 1], side[i]), d_next = d(side[i], side[i + 1]);
    if (std::min(d_prev, d_next) > 100.0 && d_prev + d_next > 10.0 * d(side[i - 1], side[i + 1])) {
      const std::string what = "point " + std::to_string(static_cast<long>(std::min(d_prev, d_next))) +
                               " m away from both its neighbours (an outlier)";
      if (!robust) throw InputError(Where(file, side[i]->line), what + "; fix it or use --robust");
      Log(LogKind::kWarning, Where(file, side[i]->line) + ": " + what + "; kept for the robust fit");
    }
  }
}

void CheckSides(const std::string& file, const std::string& format, const std::vector<Observation>& points,
                bool robust) {
  const bool borders = format == "border-points" || format == "border-pairs";
  const std::vector<Side> sides = borders ? std::vector<Side>{Side::kLeft, Side::kRight} : std::vector<Side>{Side::kCentre};
  for (Side s : sides) {
    const auto side = OfSide(points, s);
    if (side.empty() && borders)
      throw InputError(file, std::string("no ") + SideName(s) + " border points (both left and right expected)");
    if (side.size() < kMinPoints)
      throw InputError(file, std::to_string(side.size()) + " " + SideName(s) + " points, at least " +
                                 std::to_string(kMinPoints) + " expected");
    CheckSpikes(file, side, robust);
  }
}

void CheckWidth(const std::string& file, double default_width, std::vector<Observation>* points) {
  for (Observation& o : *points) {
    if (o.side != Side::kCentre) continue;
    if (std::isnan(o.width_m)) o.width_m = default_width;
    if (std::isnan(o.width_m))
      throw InputError(file, "no width column (width, or w_tr_right_m + w_tr_left_m) and no --width");
    if (!(o.width_m > 0)) throw InputError(Where(file, o.line), "width " + std::to_string(o.width_m) + " m is not positive (> 0 m expected)");
  }
}

void CheckElevation(const std::string& file, const std::vector<Observation>& points) {
  for (const Observation& o : points)
    if (std::abs(o.z_m) > kMaxAbsElevationM)
      throw InputError(Where(file, o.line), "elevation " + std::to_string(o.z_m) + " m is not plausible (|z| <= 9000 m expected)");
}

}  // namespace

RoadInput ReadRoadInput(const std::string& path, const ReadOptions& options) {
  if (!std::filesystem::exists(path)) throw InputError(path, "file not found");
  const RawInput raw = IsGdalVectorFile(path) ? ReadGdalLine(path) : ReadCsvForms(path);
  if (raw.geographic) CheckGeographic(path, raw);
  RoadInput input;
  input.file = path;
  input.format = raw.format;
  if (raw.points.empty()) throw InputError(path, "no data rows");
  input.frame = FrameFor(raw);
  input.points = DropDuplicates(path, ToLocal(raw, input.frame));
  CheckSides(path, raw.format, input.points, options.robust);
  CheckWidth(path, options.width_m, &input.points);
  const bool has_z = std::none_of(raw.points.begin(), raw.points.end(), [](const RawPoint& p) { return std::isnan(p.z); });
  if (has_z && !options.elevation_source.empty())
    Log(LogKind::kWarning, path + ": has its own elevation; --elevation " + options.elevation_source + " is ignored");
  if (!has_z && !options.elevation_source.empty()) AttachElevation(options.elevation_source, path, input.frame, &input.points);
  input.has_elevation = has_z || !options.elevation_source.empty();
  const bool borders = raw.format == "border-points" || raw.format == "border-pairs";
  input.carries_banking = (borders && has_z) || std::any_of(input.points.begin(), input.points.end(), [](const Observation& o) {
                            return std::isfinite(o.banking_rad);
                          });
  if (!input.has_elevation) Log(LogKind::kWarning, path + ": no elevation; the road is flat (give --elevation)");
  CheckElevation(path, input.points);
  return input;
}

}  // namespace ttz::road
