// Elevation for points that have none: a raster (bilinear) or a reference polyline CSV.
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <memory>

#include "common/csv.h"
#include "common/error.h"
#include "road_fit/input_forms.h"
#include "road_fit/station.h"

namespace ttz::road {
namespace {

void FromRaster(const std::string& raster, const std::string& input_file, const LocalFrame& frame,
                std::vector<Observation>* points) {
  GDALAllRegister();
  std::unique_ptr<GDALDataset> ds(static_cast<GDALDataset*>(GDALOpenEx(raster.c_str(), GDAL_OF_RASTER, nullptr, nullptr, nullptr)));
  if (!ds || ds->GetRasterCount() < 1) throw InputError(raster, "cannot be read as a raster by GDAL");
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) throw InputError(raster, "has no geotransform (a georeferenced raster expected)");
  OGRSpatialReference wgs84, target;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  if (const OGRSpatialReference* srs = ds->GetSpatialRef()) target = *srs;
  else target = wgs84;
  target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_raster(OGRCreateCoordinateTransformation(&wgs84, &target));
  GDALRasterBand* band = ds->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  for (Observation& o : *points) {
    const LatLon ll = frame.Inverse({o.x_m, o.y_m});
    double x = ll.lon_deg, y = ll.lat_deg;
    to_raster->Transform(1, &x, &y);
    // Pixel coordinates of the point relative to pixel centres (north-up geotransform).
    const double col = (x - gt[0]) / gt[1] - 0.5, row = (y - gt[3]) / gt[5] - 0.5;
    const int c0 = static_cast<int>(std::floor(col)), r0 = static_cast<int>(std::floor(row));
    float window[4];
    const std::string where = Where(input_file, o.line);
    if (c0 < 0 || r0 < 0 || c0 + 1 >= band->GetXSize() || r0 + 1 >= band->GetYSize())
      throw InputError(where, "point outside the elevation raster " + raster);
    if (band->RasterIO(GF_Read, c0, r0, 2, 2, window, 2, 2, GDT_Float32, 0, 0) != CE_None)
      throw InputError(raster, "cannot be read");
    for (float v : window)
      if (has_nodata && v == static_cast<float>(nodata)) throw InputError(where, "no elevation in the raster " + raster + " here (nodata)");
    const double fc = col - c0, fr = row - r0;
    o.z_m = (1 - fr) * ((1 - fc) * window[0] + fc * window[1]) + fr * ((1 - fc) * window[2] + fc * window[3]);
  }
}

void FromPolyline(const std::string& csv, const LocalFrame& frame, std::vector<Observation>* points) {
  const CsvTable t = ReadCsv(csv);
  const int lat = t.FindColumn({"lat", "lat_deg", "latitude"}), lon = t.FindColumn({"lon", "lon_deg", "lng", "longitude"});
  const int elev = t.FindColumn({"elevation", "elev", "elev_m", "alt", "altitude", "z", "elevation_m"});
  if (lat < 0 || lon < 0 || elev < 0) throw InputError(csv, "an elevation polyline needs lat,lon,elevation columns");
  std::vector<PointXY> vertices;
  std::vector<double> z;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const EastNorth p = frame.Forward({t.Number(r, lat), t.Number(r, lon)});
    vertices.push_back({p.x_m, p.y_m});
    z.push_back(t.Number(r, elev));
  }
  if (vertices.size() < 2) throw InputError(csv, "an elevation polyline needs at least 2 points");
  for (Side side : {Side::kLeft, Side::kRight, Side::kCentre}) {  // each side in its own order
    std::vector<Observation*> members;
    std::vector<PointXY> xy;
    for (Observation& o : *points)
      if (o.side == side) members.push_back(&o), xy.push_back({o.x_m, o.y_m});
    const std::vector<Station> st = ProjectOntoPolyline(vertices, false, xy);
    for (size_t i = 0; i < members.size(); ++i)
      members[i]->z_m = (1 - st[i].t) * z[st[i].interval] + st[i].t * z[st[i].interval + 1];
  }
}

}  // namespace

void AttachElevation(const std::string& source, const std::string& input_file, const std::optional<LocalFrame>& frame,
                     std::vector<Observation>* points) {
  if (!frame) throw InputError(source, "elevation sources need a geographic input (lat/lon), not local metres");
  const std::string ext = ToLower(source.substr(source.find_last_of('.') + 1));
  if (ext == "csv") FromPolyline(source, *frame, points);
  else FromRaster(source, input_file, *frame, points);
}

}  // namespace ttz::road
