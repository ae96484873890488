// WGS84 latitude/longitude <-> a local metric frame (PROJ).
//
// The frame is a transverse Mercator projection with scale factor 1 centred on the data (its
// centroid), so lengths within 50 km of the centre are true to about 3e-5, and x points east, y
// north, in metres from the centre. Its PROJ string and origin go into every artefact so that any
// output maps back to lat/lon. Heights are passed through unchanged (metres above the datum of the
// input).
#pragma once

#include <memory>
#include <string>

namespace ttz {

struct LatLon {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
};

struct EastNorth {
  double x_m = 0.0;  // east of the frame origin
  double y_m = 0.0;  // north of the frame origin
};

class LocalFrame {
 public:
  // The frame centred on (lat0, lon0), which must be valid WGS84 coordinates.
  static LocalFrame CentredOn(const LatLon& origin);
  // Re-creates a frame from the PROJ string stored in an artefact.
  static LocalFrame FromProjString(const std::string& proj_string);

  LocalFrame(const LocalFrame&);
  LocalFrame& operator=(const LocalFrame&);
  ~LocalFrame();

  EastNorth Forward(const LatLon& p) const;
  LatLon Inverse(const EastNorth& p) const;

  const std::string& ProjString() const;  // "+proj=tmerc +lat_0=... +lon_0=... +k=1 ..."
  std::string Wkt() const;                // WKT2 of the projected CRS
  LatLon Origin() const;

 private:
  LocalFrame();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ttz
