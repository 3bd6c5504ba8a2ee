#include "odometry/estimator/config/visual_factor_config.h"

#include <cmath>

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const char* field, const char* rule, T value) {
  return FieldMustBe("visual", field, rule, value);
}

}  // namespace

Status VisualScheduleConfig::Validate() const {
  if (!Positive(tolerance_px)) return Bad("schedule.tolerance_px", "finite and > 0", tolerance_px);
  if (min_tracks < 0) return Bad("schedule.min_tracks", ">= 0", min_tracks);
  if (!Positive(reference_tracks))
    return Bad("schedule.reference_tracks", "finite and > 0", reference_tracks);
  if (!Positive(residual_threshold_px))
    return Bad("schedule.residual_threshold_px", "finite and > 0", residual_threshold_px);
  if (!(threshold > 0 && threshold < 1)) return Bad("schedule.threshold", "in (0, 1)", threshold);
  if (!(release_margin >= 0 && release_margin < threshold))
    return Bad("schedule.release_margin", "in [0, threshold)", release_margin);
  if (release_frames < 1) return Bad("schedule.release_frames", ">= 1", release_frames);
  if (!Positive(max_shut_s)) return Bad("schedule.max_shut_s", "finite and > 0", max_shut_s);
  return {};
}

Status VisualFactorConfig::Validate() const {
  if (Status s = ValidateFeatureTrackerConfig(tracker); !s.ok())
    return Status::Error("visual.tracker." + s.message());
  if (!Positive(pixel_sigma_px)) return Bad("pixel_sigma_px", "finite and > 0", pixel_sigma_px);
  if (!Positive(huber_sigmas)) return Bad("huber_sigmas", "finite and > 0", huber_sigmas);
  if (!(std::isfinite(min_parallax_deg) && min_parallax_deg >= 0 && min_parallax_deg < 90))
    return Bad("min_parallax_deg", "in [0, 90)", min_parallax_deg);
  if (!Positive(min_depth_m)) return Bad("min_depth_m", "finite and > 0", min_depth_m);
  if (!(std::isfinite(max_depth_m) && max_depth_m > min_depth_m))
    return Bad("max_depth_m", "finite and > min_depth_m", max_depth_m);
  if (!Positive(max_reprojection_px))
    return Bad("max_reprojection_px", "finite and > 0", max_reprojection_px);
  if (!(std::abs(time_offset_s) <= 1.0)) return Bad("time_offset_s", "in [-1, 1]", time_offset_s);
  if (!Positive(time_offset_sigma_s))
    return Bad("time_offset_sigma_s", "finite and > 0", time_offset_sigma_s);
  if (!Positive(extrinsic_rotation_sigma_deg))
    return Bad("extrinsic_rotation_sigma_deg", "finite and > 0", extrinsic_rotation_sigma_deg);
  if (!Positive(extrinsic_translation_sigma_m))
    return Bad("extrinsic_translation_sigma_m", "finite and > 0", extrinsic_translation_sigma_m);
  if (max_iterations < 1) return Bad("max_iterations", ">= 1", max_iterations);
  if (!Positive(max_static_flow_px)) return Bad("max_static_flow_px", "finite and > 0", max_static_flow_px);
  if (!Positive(max_solver_time_s)) return Bad("max_solver_time_s", "finite and > 0", max_solver_time_s);
  return schedule.Validate();
}

}  // namespace uf::estimator
