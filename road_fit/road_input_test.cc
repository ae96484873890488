// The road input readers: every form, elevation sources, and the real files of ../shared/data.
#include "road_fit/road_input.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>

#include "common/error.h"

namespace ttz::road {
namespace {

const std::string kData = TTZ_SHARED_DATA;

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

size_t CountSide(const RoadInput& in, Side side) {
  return std::count_if(in.points.begin(), in.points.end(), [&](const Observation& o) { return o.side == side; });
}

std::string CentreLine(int n) {
  std::string t = "lat,lon\n";
  for (int i = 0; i < n; ++i) t += std::to_string(54.2 + i * 1e-4) + "," + std::to_string(-4.5 + i * 5e-5) + "\n";
  return t;
}

TEST(RoadInput, LocalLongFormWithSideAliases) {
  std::string t = "Side,X_M,y,z\n";
  for (int i = 0; i < 12; ++i) t += "l," + std::to_string(i * 5.0) + ",3.5,1\nR," + std::to_string(i * 5.0) + ",-3.5,1\n";
  const RoadInput in = ReadRoadInput(Write("local.csv", t), {});
  EXPECT_EQ(in.format, "border-points");
  EXPECT_FALSE(in.frame.has_value());
  EXPECT_EQ(CountSide(in, Side::kLeft), 12u);
  EXPECT_EQ(CountSide(in, Side::kRight), 12u);
  EXPECT_TRUE(in.has_elevation);
  EXPECT_TRUE(in.carries_banking);  // its borders' own elevations
}

// The banking is fitted where the input carries it: border points with their own elevations, or
// a centre line's banking column; not borders whose elevations come from --elevation, nor a
// centre line without the column.
TEST(RoadInput, WhatCarriesTheBanking) {
  std::string geographic = "side,lat,lon\n";
  for (int i = 0; i < 12; ++i)
    for (const char* side : {"left", "right"})
      geographic += std::string(side) + "," + std::to_string(54.2 + i * 1e-4) + "," +
                    std::to_string(-4.5 + (side[0] == 'l' ? -5e-5 : 5e-5)) + "\n";
  ReadOptions options;
  options.elevation_source = Write("poly_b.csv", "lat,lon,elevation\n54.19,-4.5,10\n54.21,-4.5,30\n");
  EXPECT_FALSE(ReadRoadInput(Write("borders_dem.csv", geographic), options).carries_banking);
  options.width_m = 7;
  EXPECT_FALSE(ReadRoadInput(Write("centre_b.csv", CentreLine(20)), options).carries_banking);
  std::string banked = "x_m,y_m,width,banking_deg\n";
  for (int i = 0; i < 12; ++i) banked += std::to_string(i * 5.0) + ",0,7," + std::to_string(-i) + "\n";
  const RoadInput in = ReadRoadInput(Write("banked_b.csv", banked), {});
  EXPECT_TRUE(in.carries_banking);
  EXPECT_NEAR(in.points[5].banking_rad, -5.0 * M_PI / 180.0, 1e-12);
}

TEST(RoadInput, GeographicCentreLineGetsAFrameAndTheDefaultWidth) {
  ReadOptions options;
  options.width_m = 6.5;
  const RoadInput in = ReadRoadInput(Write("centre.csv", CentreLine(20)), options);
  ASSERT_TRUE(in.frame.has_value());
  EXPECT_EQ(in.points.size(), 20u);
  EXPECT_DOUBLE_EQ(in.points[3].width_m, 6.5);
  EXPECT_FALSE(in.has_elevation);
  EXPECT_EQ(in.points[0].line, 2);
}

TEST(RoadInput, RasterElevationIsSampledBilinearly) {
  // A GeoTIFF in WGS84 holding the plane z = 100 + 2000 (lat - 54.2) + 1000 (lon + 4.5).
  GDALAllRegister();
  const std::string tif = ::testing::TempDir() + "plane.tif";
  {
    std::unique_ptr<GDALDataset> ds(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(tif.c_str(), 50, 50, 1, GDT_Float32, nullptr));
    const double cell = 1e-3, west = -4.52, north = 54.23;
    double gt[6] = {west, cell, 0, north, 0, -cell};
    ds->SetGeoTransform(gt);
    ds->SetProjection("GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]]");
    std::vector<float> z(50 * 50);
    for (int r = 0; r < 50; ++r)
      for (int c = 0; c < 50; ++c) {
        const double lat = north - (r + 0.5) * cell, lon = west + (c + 0.5) * cell;
        z[r * 50 + c] = static_cast<float>(100 + 2000 * (lat - 54.2) + 1000 * (lon + 4.5));
      }
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 50, 50, z.data(), 50, 50, GDT_Float32, 0, 0), CE_None);
  }
  ReadOptions options;
  options.width_m = 7;
  options.elevation_source = tif;
  const RoadInput in = ReadRoadInput(Write("centre_raster.csv", CentreLine(20)), options);
  for (int i = 0; i < 20; ++i) {
    const double expected = 100 + 2000 * (i * 1e-4) + 1000 * (i * 5e-5);
    EXPECT_NEAR(in.points[i].z_m, expected, 2e-4) << i;  // float32 raster
  }
}

TEST(RoadInput, PolylineElevationIsCarriedByProjection) {
  const std::string poly = Write("poly.csv", "lat_deg,lon_deg,elev_m\n54.19,-4.5,10\n54.21,-4.5,30\n");
  std::string t = "lat,lon,width\n";
  for (int i = 0; i < 11; ++i) t += std::to_string(54.195 + i * 1e-3) + ",-4.5001,7\n";
  ReadOptions options;
  options.elevation_source = poly;
  const RoadInput in = ReadRoadInput(Write("centre_poly.csv", t), options);
  EXPECT_NEAR(in.points[0].z_m, 15.0, 0.01);
  EXPECT_NEAR(in.points[10].z_m, 25.0, 0.01);
}

TEST(RoadInput, GpxTrackIsACentreLine) {
  std::string gpx = "<?xml version=\"1.0\"?>\n<gpx version=\"1.1\" creator=\"test\" xmlns=\"http://www.topografix.com/GPX/1/1\"><trk><trkseg>\n";
  for (int i = 0; i < 15; ++i)
    gpx += "<trkpt lat=\"" + std::to_string(54.2 + i * 1e-4) + "\" lon=\"-4.5\"><ele>" + std::to_string(50 + i) + "</ele></trkpt>\n";
  gpx += "</trkseg></trk></gpx>\n";
  ReadOptions options;
  options.width_m = 7;
  const RoadInput in = ReadRoadInput(Write("track.gpx", gpx), options);
  EXPECT_EQ(in.format, "gdal-line");
  EXPECT_EQ(in.points.size(), 15u);
  // GDAL 3.6's GPX driver gives track lines without Z even with ELE_AS_25D (checked with
  // ogrinfo): GPX elevations are not read; --elevation supplies them (docs/road_fit_inputs.md).
  EXPECT_FALSE(in.has_elevation);
}

TEST(RoadInput, SnaefellOsmWithFlightGearElevation) {
  ReadOptions options;
  options.width_m = 7;
  options.elevation_source = kData + "/snaefell/elevation-flightgear.csv";
  const RoadInput in = ReadRoadInput(kData + "/snaefell/centreline-osm.csv", options);
  EXPECT_EQ(in.points.size(), 1934u);
  const auto [lo, hi] = std::minmax_element(in.points.begin(), in.points.end(),
                                            [](const Observation& a, const Observation& b) { return a.z_m < b.z_m; });
  EXPECT_GT(lo->z_m, 0.0);
  EXPECT_LT(hi->z_m, 430.0);
  EXPECT_GT(hi->z_m, 400.0);
}

TEST(RoadInput, RealTracksInEveryForm) {
  ReadOptions options;
  options.width_m = 7;
  EXPECT_EQ(ReadRoadInput(kData + "/snaefell/centreline-osm.geojson", options).points.size(), 1934u);
  const RoadInput panorama = ReadRoadInput(kData + "/tracks/mount-panorama-borders-3d.csv", {});
  EXPECT_EQ(panorama.format, "border-pairs");
  EXPECT_GT(CountSide(panorama, Side::kLeft), 5990u);  // 6001 pairs less a few duplicates
  for (const char* track : {"Spa", "Nuerburgring", "Catalunya"}) {
    const RoadInput in = ReadRoadInput(kData + "/tracks/" + track + "-centreline-widths.csv", {});
    EXPECT_EQ(in.format, "centre-line") << track;
    EXPECT_GT(in.points.front().width_m, 10.0) << track;  // right + left
  }
  const RoadInput oval = ReadRoadInput(kData + "/tracks/las-vegas-centreline-banking.csv", {});
  EXPECT_EQ(oval.points.size(), 9762u);
  EXPECT_TRUE(oval.carries_banking);
  EXPECT_NEAR(oval.points.front().banking_rad, -0.1571, 1e-12);  // its first row's banking_rad
  EXPECT_TRUE(panorama.carries_banking);
}

TEST(RoadInput, LocalInputCannotUseAnElevationSource) {
  std::string t = "x_m,y_m,width\n";
  for (int i = 0; i < 12; ++i) t += std::to_string(i * 5.0) + ",0,7\n";
  ReadOptions options;
  options.elevation_source = Write("p.csv", "lat,lon,elevation\n54,-4,1\n54.1,-4,2\n");
  EXPECT_THROW(ReadRoadInput(Write("local_centre.csv", t), options), InputError);
}

}  // namespace
}  // namespace ttz::road
