#include "odometry/eval/gnss_georeference.h"

#include <cstdio>

namespace uf {

GnssGeoreference GeoreferenceFromGnss(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                      const std::optional<SE3>& T_body_gnss, const SE3& T_estimator_body,
                                      bool gravity_aligned) {
  GnssGeoreference result;
  if (fixes.empty()) return result;
  GnssAlignmentOptions options;
  options.T_body_antenna = T_estimator_body * T_body_gnss.value_or(SE3());
  options.gravity_aligned = gravity_aligned;
  Expected<GnssAlignment> aligned = AlignToGnss(trajectory, fixes, options);
  if (!aligned) {
    result.note = "map not georeferenced: " + aligned.status().message();
    return result;
  }
  char text[200];
  std::snprintf(text, sizeof(text),
                "map georeferenced by %d GNSS fixes (residual RMS %.2f m): ENU at %.7f, %.7f, %.2f m",
                aligned->fixes_used, aligned->rms_m, aligned->origin.latitude_deg,
                aligned->origin.longitude_deg, aligned->origin.height_m);
  result.note = text;
  result.alignment = *aligned;
  return result;
}

}  // namespace uf
