#include "common/geodesy.h"

#include <proj.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ttz {

struct LocalFrame::Impl {
  PJ_CONTEXT* context = nullptr;
  PJ* transform = nullptr;
  std::string proj_string;
  LatLon origin;

  explicit Impl(const std::string& definition) : proj_string(definition) {
    context = proj_context_create();
    PJ* raw = proj_create_crs_to_crs(context, "EPSG:4326", definition.c_str(), nullptr);
    if (!raw) {
      proj_context_destroy(context);
      throw std::runtime_error("PROJ cannot create the local frame '" + definition + "'");
    }
    transform = proj_normalize_for_visualization(context, raw);  // lon, lat order
    proj_destroy(raw);
  }
  ~Impl() {
    proj_destroy(transform);
    proj_context_destroy(context);
  }
};

namespace {
double Parameter(const std::string& definition, const std::string& key) {
  const size_t at = definition.find("+" + key + "=");
  if (at == std::string::npos) return 0.0;
  return std::stod(definition.substr(at + key.size() + 2));
}
}  // namespace

LocalFrame::LocalFrame() = default;
LocalFrame::~LocalFrame() = default;
LocalFrame::LocalFrame(const LocalFrame& other) : impl_(new Impl(other.impl_->proj_string)) {
  impl_->origin = other.impl_->origin;
}
LocalFrame& LocalFrame::operator=(const LocalFrame& other) {
  if (this != &other) {
    impl_.reset(new Impl(other.impl_->proj_string));
    impl_->origin = other.impl_->origin;
  }
  return *this;
}

LocalFrame LocalFrame::CentredOn(const LatLon& origin) {
  char definition[256];
  std::snprintf(definition, sizeof definition,
                "+proj=tmerc +lat_0=%.9f +lon_0=%.9f +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs +type=crs",
                origin.lat_deg, origin.lon_deg);
  return FromProjString(definition);
}

LocalFrame LocalFrame::FromProjString(const std::string& proj_string) {
  LocalFrame frame;
  frame.impl_.reset(new Impl(proj_string));
  frame.impl_->origin = {Parameter(proj_string, "lat_0"), Parameter(proj_string, "lon_0")};
  return frame;
}

EastNorth LocalFrame::Forward(const LatLon& p) const {
  const PJ_COORD out = proj_trans(impl_->transform, PJ_FWD, proj_coord(p.lon_deg, p.lat_deg, 0, 0));
  return {out.xy.x, out.xy.y};
}

LatLon LocalFrame::Inverse(const EastNorth& p) const {
  const PJ_COORD out = proj_trans(impl_->transform, PJ_INV, proj_coord(p.x_m, p.y_m, 0, 0));
  return {out.lp.phi, out.lp.lam};
}

const std::string& LocalFrame::ProjString() const { return impl_->proj_string; }

std::string LocalFrame::Wkt() const {
  PJ* crs = proj_create(impl_->context, impl_->proj_string.c_str());
  const char* wkt = crs ? proj_as_wkt(impl_->context, crs, PJ_WKT2_2019, nullptr) : nullptr;
  std::string text = wkt ? wkt : "";
  proj_destroy(crs);
  return text;
}

LatLon LocalFrame::Origin() const { return impl_->origin; }

}  // namespace ttz
