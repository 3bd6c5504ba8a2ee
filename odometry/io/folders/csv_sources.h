// StreamSources over the per-sensor CSV files that EuRoC ASL and the project's own format share. Every
// file has integer nanosecond stamps in the first column, strictly increasing; lines starting with '#' are
// comments (EuRoC's header line is one). Internal to uf_io.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "odometry/io/folders/merged_streams.h"

namespace uf {

// `stamp_ns, gx, gy, gz, ax, ay, az`: angular velocity (rad/s) then specific force (m/s^2), IMU frame. This
// is EuRoC's imu0/data.csv column order.
Expected<std::unique_ptr<StreamSource>> OpenImuCsv(const std::filesystem::path& path);

// `stamp_ns, vx, vy, vz, wx, wy, wz`: linear (m/s) then angular (rad/s) velocity, wheel/base frame.
Expected<std::unique_ptr<StreamSource>> OpenWheelCsv(const std::filesystem::path& path);

// `stamp_ns, latitude_deg, longitude_deg, altitude_m, c00 .. c22, status`: WGS84 position (altitude above
// the ellipsoid), the 3x3 ENU position covariance row-major (m^2), and a GnssFixStatusName.
Expected<std::unique_ptr<StreamSource>> OpenGnssCsv(const std::filesystem::path& path);

// `stamp_ns, filename`: one image file per frame in `image_folder` (PNG or JPEG, told by the file's first
// bytes). The bytes are read when the frame is delivered; a missing or unreadable image is skipped with a
// warning on `stream_name`.
Expected<std::unique_ptr<StreamSource>> OpenCameraCsv(const std::filesystem::path& path,
                                                      const std::filesystem::path& image_folder, int camera,
                                                      const std::string& stream_name);

// "no_fix", "fix", "sbas", "rtk_float", "rtk_fixed", and back.
std::string_view GnssFixStatusName(GnssFixStatus status);
bool ParseGnssFixStatus(std::string_view name, GnssFixStatus& status);

// "png" or "jpeg" from the file's signature; empty when it is neither.
std::string ImageFormatOf(const std::vector<std::uint8_t>& bytes);

}  // namespace uf
