// Validation of the camera configuration and its intrinsics as the project's camera model.
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "odometry/sim/sensors/camera_renderer.h"

namespace uf::sim {
namespace {

constexpr int kMaxImageSize = 16384;   // pixels per side
constexpr int kMaxSupersampling = 16;  // n of the n x n sub-samples

template <typename T>
Status FieldError(const std::string& field, const std::string& requirement, const T& got) {
  std::ostringstream message;
  message.precision(12);
  message << "camera." << field << ": " << requirement << ", got " << got;
  return Status::Error(message.str());
}

bool PositiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

Status ValidateWindow(const std::string& field, const TimeWindow& window) {
  if (window.end > window.begin) return Status();
  std::ostringstream got;  // (a stream, not string concatenation: gcc 12 warns falsely on the latter here)
  got << "[" << FormatSeconds(window.begin) << ", " << FormatSeconds(window.end) << "] s";
  return FieldError(field, "end must be after begin", got.str());
}

// Each window of a list, named "<field>[i]".
Status ValidateWindows(const std::string& field, const std::vector<TimeWindow>& windows) {
  for (std::size_t i = 0; i < windows.size(); ++i)
    if (Status s = ValidateWindow(field + "[" + std::to_string(i) + "]", windows[i]); !s.ok()) return s;
  return Status();
}

}  // namespace

Status ValidateCameraConfig(const CameraConfig& c) {
  const PinholeIntrinsics& p = c.pinhole;
  if (p.width < 1 || p.width > kMaxImageSize) return FieldError("width", "must be in [1, 16384]", p.width);
  if (p.height < 1 || p.height > kMaxImageSize) {
    return FieldError("height", "must be in [1, 16384]", p.height);
  }
  if (!PositiveFinite(p.fx)) return FieldError("fx", "must be positive and finite", p.fx);
  if (!PositiveFinite(p.fy)) return FieldError("fy", "must be positive and finite", p.fy);
  // The principal point inside the image: [-0.5, width - 0.5] x [-0.5, height - 0.5] (pixel centres).
  if (!(p.cx >= -0.5 && p.cx <= p.width - 0.5)) {
    return FieldError("cx", "must be inside the image [-0.5, " + std::to_string(p.width) + " - 0.5]", p.cx);
  }
  if (!(p.cy >= -0.5 && p.cy <= p.height - 0.5)) {
    return FieldError("cy", "must be inside the image [-0.5, " + std::to_string(p.height) + " - 0.5]", p.cy);
  }
  for (const auto& [name, value] : {std::pair{"k1", c.k1}, std::pair{"k2", c.k2}, std::pair{"p1", c.p1},
                                    std::pair{"p2", c.p2}, std::pair{"k3", c.k3}}) {
    if (!std::isfinite(value)) return FieldError(name, "must be finite", value);
  }
  if (!(c.rate_hz > 0.0 && c.rate_hz <= 1000.0))
    return FieldError("rate_hz", "must be in (0, 1000]", c.rate_hz);
  if (!(c.noise_std_dn >= 0.0 && c.noise_std_dn <= 255.0)) {
    return FieldError("noise_std_dn", "must be in [0, 255]", c.noise_std_dn);
  }
  if (c.supersampling < 1 || c.supersampling > kMaxSupersampling) {
    return FieldError("supersampling", "must be in [1, 16]", c.supersampling);
  }
  if (!c.sun_direction_world.allFinite() || !(c.sun_direction_world.norm() > 1e-9)) {
    return FieldError("sun_direction_world", "must be a finite non-zero vector",
                      c.sun_direction_world.transpose());
  }
  if (!(c.ambient >= 0.0 && c.ambient <= 1.0)) return FieldError("ambient", "must be in [0, 1]", c.ambient);
  if (!PositiveFinite(c.exposure)) return FieldError("exposure", "must be positive and finite", c.exposure);
  if (Status s = ValidateWindows("darkness", c.darkness); !s.ok()) return s;
  for (std::size_t i = 0; i < c.exposure_changes.size(); ++i) {
    const std::string field = "exposure_changes[" + std::to_string(i) + "]";
    if (Status s = ValidateWindow(field, c.exposure_changes[i].first); !s.ok()) return s;
    if (!PositiveFinite(c.exposure_changes[i].second)) {
      return FieldError(field + ".gain", "must be positive and finite", c.exposure_changes[i].second);
    }
  }
  if (Status s = ValidateWindows("occlusions", c.occlusions); !s.ok()) return s;
  if (Status s = ValidateWindows("passing_panels", c.passing_panels); !s.ok()) return s;
  if (c.threads < 0) return FieldError("threads", "must be >= 0 (0: all cores)", c.threads);
  return Status();
}

PinholeRadtan CameraModelOf(const CameraConfig& c) {
  return PinholeRadtan(PinholeRadtanIntrinsics{c.pinhole, c.k1, c.k2, c.p1, c.p2, c.k3});
}

}  // namespace uf::sim
