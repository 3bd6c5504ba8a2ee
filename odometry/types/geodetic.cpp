#include "odometry/types/geodetic.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace uf {

struct EnuFrame::Impl {
  GeographicLib::LocalCartesian enu;  // ENU tangent frame at the origin on the WGS84 ellipsoid (the default)
};

namespace {

// The value with the fewest significant digits (at least 6) that reads back as the same double: "91",
// "-180.5", "200000", "90.00000000000001", "nan".
std::string Text(double value) {
  char text[32];
  for (int digits = 6;; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (digits >= 17 || std::strtod(text, nullptr) == value) return text;
  }
}

}  // namespace

Status ValidateGeodeticOrigin(const GeodeticOrigin& origin) {
  // Written as "not inside" so that NaN fails too.
  if (!(origin.latitude_deg >= -90.0 && origin.latitude_deg <= 90.0))
    return Status::Error("origin.latitude_deg: must be in [-90, 90], got " + Text(origin.latitude_deg));
  if (!(origin.longitude_deg >= -180.0 && origin.longitude_deg <= 180.0))
    return Status::Error("origin.longitude_deg: must be in [-180, 180], got " + Text(origin.longitude_deg));
  if (!(origin.height_m >= -12e3 && origin.height_m <= 100e3))
    return Status::Error("origin.height_m: must be in [-12000, 100000] m, got " + Text(origin.height_m));
  return Status();
}

Expected<EnuFrame> EnuFrame::Create(const GeodeticOrigin& origin) {
  if (Status s = ValidateGeodeticOrigin(origin); !s.ok()) return s;
  auto impl = std::make_shared<Impl>(
      Impl{GeographicLib::LocalCartesian(origin.latitude_deg, origin.longitude_deg, origin.height_m)});
  return EnuFrame(origin, std::move(impl));
}

EnuFrame::EnuFrame(const GeodeticOrigin& origin, std::shared_ptr<const Impl> impl)
    : origin_(origin), impl_(std::move(impl)) {}

Eigen::Vector3d EnuFrame::GeodeticFromEnu(const Eigen::Vector3d& enu) const {
  Eigen::Vector3d lat_lon_h;
  impl_->enu.Reverse(enu.x(), enu.y(), enu.z(), lat_lon_h.x(), lat_lon_h.y(), lat_lon_h.z());
  return lat_lon_h;
}

Eigen::Vector3d EnuFrame::EnuFromGeodetic(const Eigen::Vector3d& lat_lon_h) const {
  Eigen::Vector3d enu;
  impl_->enu.Forward(lat_lon_h.x(), lat_lon_h.y(), lat_lon_h.z(), enu.x(), enu.y(), enu.z());
  return enu;
}

Eigen::Vector3d GeodeticFromEnu(const GeodeticOrigin& origin, const Eigen::Vector3d& enu) {
  const Expected<EnuFrame> frame = EnuFrame::Create(origin);
  assert(frame.ok());
  return frame->GeodeticFromEnu(enu);
}

Eigen::Vector3d EnuFromGeodetic(const GeodeticOrigin& origin, const Eigen::Vector3d& lat_lon_h) {
  const Expected<EnuFrame> frame = EnuFrame::Create(origin);
  assert(frame.ok());
  return frame->EnuFromGeodetic(lat_lon_h);
}

}  // namespace uf
