// Any line layer GDAL reads (GeoJSON, GPX, KML, Shapefile, GeoPackage) as a geographic centre line.
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <memory>

#include "common/csv.h"
#include "common/error.h"
#include "road_fit/input_forms.h"

namespace ttz::road {
namespace {

bool IsLine(OGRwkbGeometryType type) {
  const auto flat = wkbFlatten(type);
  return flat == wkbLineString || flat == wkbMultiLineString;
}

void AppendLine(const OGRLineString& line, long feature, RawInput* in) {
  for (int i = 0; i < line.getNumPoints(); ++i) {
    RawPoint p;
    p.u = line.getY(i);  // latitude (traditional GIS order: x = lon)
    p.v = line.getX(i);
    if (line.Is3D()) p.z = line.getZ(i);
    p.line = feature * 100000 + i + 1;  // feature F, vertex V -> F*100000 + V (documented)
    in->points.push_back(p);
  }
}

}  // namespace

bool IsGdalVectorFile(const std::string& path) {
  const std::string ext = ToLower(path.substr(path.find_last_of('.') + 1));
  for (const char* e : {"geojson", "json", "gpx", "kml", "shp", "gpkg"})
    if (ext == e) return true;
  return false;
}

RawInput ReadGdalLine(const std::string& path) {
  GDALAllRegister();
  std::unique_ptr<GDALDataset> ds(
      static_cast<GDALDataset*>(GDALOpenEx(path.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr)));
  if (!ds) throw InputError(path, "cannot be opened as a vector layer by GDAL");
  RawInput in;
  in.format = "gdal-line";
  in.geographic = true;
  for (OGRLayer* layer : ds->GetLayers()) {
    std::unique_ptr<OGRCoordinateTransformation> to_wgs84;
    if (const OGRSpatialReference* srs = layer->GetSpatialRef()) {
      OGRSpatialReference wgs84;
      wgs84.SetWellKnownGeogCS("WGS84");
      wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
      to_wgs84.reset(OGRCreateCoordinateTransformation(srs, &wgs84));
    }
    long feature_index = 0;
    for (auto& feature : layer) {
      ++feature_index;
      OGRGeometry* g = feature->GetGeometryRef();
      if (!g || !IsLine(g->getGeometryType())) continue;
      if (to_wgs84) g->transform(to_wgs84.get());
      if (wkbFlatten(g->getGeometryType()) == wkbLineString) AppendLine(*g->toLineString(), feature_index, &in);
      else
        for (const OGRLineString* part : *g->toMultiLineString()) AppendLine(*part, feature_index, &in);
    }
    if (!in.points.empty()) return in;
  }
  throw InputError(path, "no layer with line geometry (a LineString or MultiLineString expected)");
}

}  // namespace ttz::road
