// The CSV forms of road input: border points, border pairs and centre lines.
#include <algorithm>
#include <cmath>
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
const std::vector<std::string> kBanking = {"banking", "bank"};  // without a unit: refused
const std::vector<std::string> kBankingRad = {"banking_rad", "bank_rad"};
const std::vector<std::string> kBankingDeg = {"banking_deg", "bank_deg"};
constexpr double kMaxBankingDeg = 45.0;

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

// A centre line's banking column, in radians or degrees by its name's suffix; -1 when none.
struct BankingColumn {
  int column = -1;
  double to_rad = 1.0;
};

BankingColumn FindBanking(const CsvTable& t) {
  const int bare = t.FindColumn(kBanking);
  if (bare >= 0)
    throw InputError(t.file + ": column '" + t.header[bare] + "'",
                     "banking without a unit: name it banking_rad or banking_deg");
  if (const int rad = t.FindColumn(kBankingRad); rad >= 0) return {rad, 1.0};
  if (const int deg = t.FindColumn(kBankingDeg); deg >= 0) return {deg, M_PI / 180.0};
  return {};
}

// Row's banking [rad]; refused beyond kMaxBankingDeg (Talladega's, among the steepest, is 33 deg).
double Banking(const CsvTable& t, size_t row, const BankingColumn& c) {
  const double xi = t.Number(row, c.column) * c.to_rad;
  if (!(std::abs(xi) <= kMaxBankingDeg * M_PI / 180.0))
    throw InputError(Where(t.file, t.lines[row]) + ": column '" + t.header[c.column] + "'",
                     "banking " + t.Cell(row, c.column) + " is not within +-45 deg");
  return xi;
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
  const BankingColumn banking = FindBanking(t);
  for (size_t row = 0; row < t.rows.size(); ++row) {
    RawPoint p = PointAt(t, row, *c, Side::kCentre);
    if (width >= 0) p.width = t.Number(row, width);
    else if (w_right >= 0 && w_left >= 0) p.width = t.Number(row, w_right) + t.Number(row, w_left);
    if (banking.column >= 0) p.banking = Banking(t, row, banking);
    in.points.push_back(p);
  }
  return in;
}

// A border form's banking column says less than its borders' elevations, which the fit follows.
void WarnOfIgnoredBanking(const CsvTable& t) {
  const int rad = t.FindColumn(kBankingRad), deg = t.FindColumn(kBankingDeg), bare = t.FindColumn(kBanking);
  const int bank = std::max({rad, deg, bare});
  if (bank >= 0)
    Log(LogKind::kWarning, t.file + ": column '" + t.header[bank] +
                               "' is ignored: the banking of border points follows from their elevations");
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
  if (in.format != "centre-line") WarnOfIgnoredBanking(t);  // once read as a form: not beside an error
  return in;
}

}  // namespace ttz::road
