// The CSV forms of road input: border points, border pairs and centre lines.
#include <optional>

#include "common/csv.h"
#include "common/error.h"
#include "common/log.h"
#include "road_fit/input_forms.h"

namespace ttz::road {
namespace {

const std::vector<std::string> kLat = {"lat", "lat_deg", "latitude"};
const std::vector<std::string> kLon = {"lon", "lon_deg", "lng", "longitude"};
const std::vector<std::string> kElevation = {"elevation", "elev", "elev_m", "alt", "altitude", "z", "elevation_m",
                                             "z_m"};
const std::vector<std::string> kX = {"x", "x_m"};
const std::vector<std::string> kY = {"y", "y_m"};
const std::vector<std::string> kWidth = {"width", "width_m", "w"};
const std::vector<std::string> kBanking = {"banking", "banking_rad", "banking_deg", "bank", "bank_rad", "bank_deg"};

struct Columns {
  int u = -1, v = -1, z = -1;
};

// lat/lon columns when present (geographic), else x/y (local), else -1.
std::optional<Columns> PositionColumns(const CsvTable& t, bool* geographic) {
  Columns c;
  c.u = t.FindColumn(kLat);
  c.v = t.FindColumn(kLon);
  *geographic = c.u >= 0 && c.v >= 0;
  if (!*geographic) {
    c.u = t.FindColumn(kX);
    c.v = t.FindColumn(kY);
  }
  if (c.u < 0 || c.v < 0) return std::nullopt;
  c.z = t.FindColumn(kElevation);
  return c;
}

RawPoint PointAt(const CsvTable& t, size_t row, const Columns& c, Side side) {
  RawPoint p;
  p.side = side;
  p.u = t.Number(row, c.u);
  p.v = t.Number(row, c.v);
  if (c.z >= 0) p.z = t.Number(row, c.z);
  p.line = t.lines[row];
  return p;
}

Side ParseSide(const CsvTable& t, size_t row, int column) {
  const std::string s = ToLower(t.Cell(row, column));
  if (s == "left" || s == "l") return Side::kLeft;
  if (s == "right" || s == "r") return Side::kRight;
  throw InputError(Where(t.file, t.lines[row]) + ": column '" + t.header[column] + "'",
                   "side '" + t.Cell(row, column) + "' is not left or right");
}

RawInput LongForm(const CsvTable& t, int side_column) {
  RawInput in;
  in.format = "border-points";
  const auto c = PositionColumns(t, &in.geographic);
  if (!c) throw InputError(t.file, "border points need lat,lon (or x,y) columns beside 'side'");
  for (size_t row = 0; row < t.rows.size(); ++row) in.points.push_back(PointAt(t, row, *c, ParseSide(t, row, side_column)));
  return in;
}

// left_x,left_y[,left_z],right_x,... or right_bound_x,...,left_bound_z.
std::optional<RawInput> BorderPairs(const CsvTable& t) {
  for (const std::string suffix : {"", "_bound"}) {
    Columns left{t.FindColumn({"left" + suffix + "_x"}), t.FindColumn({"left" + suffix + "_y"}),
                 t.FindColumn({"left" + suffix + "_z"})};
    Columns right{t.FindColumn({"right" + suffix + "_x"}), t.FindColumn({"right" + suffix + "_y"}),
                  t.FindColumn({"right" + suffix + "_z"})};
    if (left.u < 0 || left.v < 0 || right.u < 0 || right.v < 0) continue;
    RawInput in;
    in.format = "border-pairs";
    for (size_t row = 0; row < t.rows.size(); ++row) in.points.push_back(PointAt(t, row, left, Side::kLeft));
    for (size_t row = 0; row < t.rows.size(); ++row) in.points.push_back(PointAt(t, row, right, Side::kRight));
    return in;
  }
  return std::nullopt;
}

RawInput CentreLine(const CsvTable& t) {
  RawInput in;
  in.format = "centre-line";
  const auto c = PositionColumns(t, &in.geographic);
  if (!c) {
    std::string found;
    for (const auto& h : t.header) found += (found.empty() ? "" : ",") + h;
    throw InputError(t.file, "unknown columns (" + found +
                                 "): expected side,lat,lon[,elevation]; left_x,left_y,right_x,right_y; "
                                 "lat,lon[,elevation][,width]; or x_m,y_m[,z][,w_tr_right_m,w_tr_left_m]");
  }
  const int width = t.FindColumn(kWidth);
  const int w_right = t.FindColumn({"w_tr_right_m"}), w_left = t.FindColumn({"w_tr_left_m"});
  for (size_t row = 0; row < t.rows.size(); ++row) {
    RawPoint p = PointAt(t, row, *c, Side::kCentre);
    if (width >= 0) p.width = t.Number(row, width);
    else if (w_right >= 0 && w_left >= 0) p.width = t.Number(row, w_right) + t.Number(row, w_left);
    in.points.push_back(p);
  }
  return in;
}

// The ribbon has no banking (paper eq. 4-8: xi = 0, road_fit/ribbon.h): a banking column, which
// the other extra columns are not, changes the road the file describes, so its user is told.
void WarnOfBanking(const CsvTable& t) {
  const int bank = t.FindColumn(kBanking);
  if (bank >= 0)
    Log(LogKind::kWarning, t.file + ": column '" + t.header[bank] +
                               "' is ignored: the ribbon has no banking (paper eq. 4-8), so the road is fitted level across");
}

// The points of the table in its form: border points (long form), border pairs or a centre line.
RawInput ReadCsvForm(const CsvTable& t) {
  const int side = t.FindColumn({"side"});
  if (side >= 0) return LongForm(t, side);
  if (auto pairs = BorderPairs(t)) return *pairs;
  return CentreLine(t);
}

}  // namespace

RawInput ReadCsvForms(const std::string& path) {
  const CsvTable t = ReadCsv(path);
  RawInput in = ReadCsvForm(t);
  WarnOfBanking(t);  // once the file has been read as one of the forms: not beside an error
  return in;
}

}  // namespace ttz::road
