#include "odometry/io/folders/kitti_raw_oxts.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "odometry/types/printf_text.h"

namespace uf {
namespace {

constexpr std::array<const char*, 30> kFields = {
    "lat",          "lon",     "alt",     "roll",    "pitch",   "yaw",    "vn", "ve",
    "vf",           "vl",      "vu",      "ax",      "ay",      "az",     "af", "al",
    "au",           "wx",      "wy",      "wz",      "wf",      "wl",     "wu", "pos_accuracy",
    "vel_accuracy", "navstat", "numsats", "posmode", "velmode", "orimode"};

// navstat, numsats, posmode are small whole numbers (KITTI's drives hold -1 too: "no mode").
constexpr double kMaxStatusValue = 1000;
constexpr double kEarthRadius = 6378137.0;  // m, WGS84 equatorial radius, as the devkit uses
constexpr double kDegToRad = M_PI / 180.0;

Status FieldError(const std::filesystem::path& path, int field, const std::string& why) {
  return Status::Error(path.string() + ": field " + std::to_string(field + 1) + " (" + kFields[field] + ") " +
                       why);
}

}  // namespace

Expected<OxtsRecord> ReadOxtsFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open the OXTS file");
  std::ostringstream text;
  text << in.rdbuf();
  std::istringstream words(text.str());
  std::array<double, kFields.size()> v{};
  std::size_t n = 0;
  for (std::string word; words >> word; ++n) {
    if (n == v.size())
      return Status::Error(path.string() + ": more than " + std::to_string(v.size()) +
                           " numbers (an OXTS record has 30: see oxts/dataformat.txt)");
    auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), v[n]);
    if (error != std::errc() || end != word.data() + word.size() || !std::isfinite(v[n]))
      return FieldError(path, static_cast<int>(n), "is '" + word.substr(0, 40) + "', not a finite number");
  }
  if (n != v.size())
    return Status::Error(path.string() + ": " + std::to_string(n) + " numbers, expected 30 (truncated?)");
  if (std::abs(v[0]) > 90)
    return FieldError(path, 0, "is " + std::to_string(v[0]) + ", outside [-90, 90] deg");
  if (std::abs(v[1]) > 180)
    return FieldError(path, 1, "is " + std::to_string(v[1]) + ", outside [-180, 180] deg");
  if (v[23] < 0) return FieldError(path, 23, "is negative (" + std::to_string(v[23]) + " m)");
  for (int i : {25, 26, 27}) {
    if (std::abs(v[i]) > kMaxStatusValue || v[i] != std::floor(v[i]))
      return FieldError(path, i,
                        PrintfText("is %g, not a whole number within +-%.0f", v[i], kMaxStatusValue));
  }
  OxtsRecord record;
  record.latitude_deg = v[0];
  record.longitude_deg = v[1];
  record.altitude_m = v[2];
  record.roll = v[3];
  record.pitch = v[4];
  record.yaw = v[5];
  record.acc = Eigen::Vector3d(v[11], v[12], v[13]);
  record.gyro = Eigen::Vector3d(v[17], v[18], v[19]);
  record.position_accuracy_m = v[23];
  record.navstat = static_cast<int>(v[25]);
  record.numsats = static_cast<int>(v[26]);
  record.posmode = static_cast<int>(v[27]);
  return record;
}

ImuSample OxtsImuSample(const OxtsRecord& record, Stamp stamp) { return {stamp, record.acc, record.gyro}; }

GnssFix OxtsGnssFix(const OxtsRecord& record, Stamp stamp) {
  GnssFix fix;
  fix.stamp = stamp;
  fix.latitude_deg = record.latitude_deg;
  fix.longitude_deg = record.longitude_deg;
  fix.altitude_m = record.altitude_m;
  const double sigma = std::max(record.position_accuracy_m, 0.02);
  fix.covariance_enu = Eigen::Vector3d(sigma * sigma, sigma * sigma, 4 * sigma * sigma).asDiagonal();
  if (record.navstat != 4) {
    fix.status = GnssFixStatus::kNoFix;
    return fix;
  }
  switch (record.posmode) {
    case 4:
    case 7:
      fix.status = GnssFixStatus::kSbas;
      break;
    case 5:
      fix.status = GnssFixStatus::kRtkFloat;
      break;
    case 6:
      fix.status = GnssFixStatus::kRtkFixed;
      break;
    default:
      fix.status = GnssFixStatus::kFix;
  }
  return fix;
}

SE3 OxtsMercatorPose(const OxtsRecord& record, double mercator_scale) {
  // Mercator projection at the given scale (devkit latlonToMercator).
  const double x = mercator_scale * record.longitude_deg * kDegToRad * kEarthRadius;
  const double y =
      mercator_scale * kEarthRadius * std::log(std::tan((90.0 + record.latitude_deg) * M_PI / 360.0));
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(record.yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(record.pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(record.roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return SE3(SO3(R), Eigen::Vector3d(x, y, record.altitude_m));
}

}  // namespace uf
