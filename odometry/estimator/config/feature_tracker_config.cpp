#include "odometry/estimator/config/feature_tracker_config.h"

#include <cmath>
#include <string>

#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

Status FieldError(const char* field, double value, const char* rule) {
  return Status::Error(std::string(field) + ": " + rule + PrintfText(", got %g", value));
}

}  // namespace

Status ValidateFeatureTrackerConfig(const FeatureTrackerConfig& c) {
  if (c.max_features < 1) return FieldError("max_features", c.max_features, "must be at least 1");
  if (!(c.min_distance_px >= 0) || !std::isfinite(c.min_distance_px))
    return FieldError("min_distance_px", c.min_distance_px, "must be finite and >= 0");
  if (!(c.quality_level > 0 && c.quality_level < 1))
    return FieldError("quality_level", c.quality_level, "must be in (0, 1)");
  if (c.klt_window_px < 5 || c.klt_window_px % 2 == 0)
    return FieldError("klt_window_px", c.klt_window_px, "must be odd and at least 5");
  if (c.klt_pyramid_levels < 0 || c.klt_pyramid_levels > 8)
    return FieldError("klt_pyramid_levels", c.klt_pyramid_levels, "must be in [0, 8]");
  if (!(c.max_fb_error_px > 0) || !std::isfinite(c.max_fb_error_px))
    return FieldError("max_fb_error_px", c.max_fb_error_px, "must be positive and finite");
  if (!(c.ransac_threshold_px > 0) || !std::isfinite(c.ransac_threshold_px))
    return FieldError("ransac_threshold_px", c.ransac_threshold_px, "must be positive and finite");
  if (!(c.ransac_confidence > 0 && c.ransac_confidence < 1))
    return FieldError("ransac_confidence", c.ransac_confidence, "must be in (0, 1)");
  if (c.min_track_length < 1) return FieldError("min_track_length", c.min_track_length, "must be at least 1");
  if (!(c.keyframe_parallax_px >= 0) || !std::isfinite(c.keyframe_parallax_px))
    return FieldError("keyframe_parallax_px", c.keyframe_parallax_px, "must be finite and >= 0");
  if (c.grid_cells < 1 || c.grid_cells > 64)
    return FieldError("grid_cells", c.grid_cells, "must be in [1, 64]");
  if (!(c.min_contrast_dn >= 0) || !std::isfinite(c.min_contrast_dn))
    return FieldError("min_contrast_dn", c.min_contrast_dn, "must be finite and >= 0");
  if (!(c.smoothing_sigma_px >= 0 && c.smoothing_sigma_px <= FeatureTrackerConfig::kMaxSmoothingSigmaPx))
    return FieldError("smoothing_sigma_px", c.smoothing_sigma_px,
                      PrintfText("must be in [0, %g]", FeatureTrackerConfig::kMaxSmoothingSigmaPx).c_str());
  return Status();
}

}  // namespace uf::estimator
