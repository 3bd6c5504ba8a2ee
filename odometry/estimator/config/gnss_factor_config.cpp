#include "odometry/estimator/config/gnss_factor_config.h"

#include <cmath>
#include <string>
#include <utility>

#include "odometry/estimator/config/field_rules.h"

namespace uf::estimator {
namespace {

template <typename T>
Status Bad(const std::string& field, const char* rule, T value) {
  return FieldMustBe("lio.gnss", field.c_str(), rule, value);
}

Status CheckNoise(const char* status, const GnssStatusNoise& noise) {
  const std::string prefix = std::string(status) + ".";
  if (!Positive(noise.min_sigma_m)) return Bad(prefix + "min_sigma_m", "> 0", noise.min_sigma_m);
  if (!(std::isfinite(noise.sigma_scale) && noise.sigma_scale >= 1))
    return Bad(prefix + "sigma_scale", "finite and >= 1", noise.sigma_scale);
  if (!Positive(noise.nominal_horizontal_sigma_m))
    return Bad(prefix + "nominal_horizontal_sigma_m", "> 0", noise.nominal_horizontal_sigma_m);
  if (!Positive(noise.nominal_vertical_sigma_m))
    return Bad(prefix + "nominal_vertical_sigma_m", "> 0", noise.nominal_vertical_sigma_m);
  if (!(noise.offset_share >= 0 && noise.offset_share < 1))
    return Bad(prefix + "offset_share", "in [0, 1)", noise.offset_share);
  return {};
}

}  // namespace

const char* GnssStatusName(GnssFixStatus status) {
  switch (status) {
    case GnssFixStatus::kNoFix:
      return "no_fix";
    case GnssFixStatus::kFix:
      return "fix";
    case GnssFixStatus::kSbas:
      return "sbas";
    case GnssFixStatus::kRtkFloat:
      return "rtk_float";
    case GnssFixStatus::kRtkFixed:
      return "rtk_fixed";
  }
  return "unknown";
}

const GnssStatusNoise& GnssFactorConfig::Noise(GnssFixStatus status) const {
  switch (status) {
    case GnssFixStatus::kSbas:
      return sbas;
    case GnssFixStatus::kRtkFloat:
      return rtk_float;
    case GnssFixStatus::kRtkFixed:
      return rtk_fixed;
    case GnssFixStatus::kNoFix:
    case GnssFixStatus::kFix:
      break;
  }
  return fix;
}

Status GnssFactorConfig::Validate() const {
  if (min_status == GnssFixStatus::kNoFix || static_cast<int>(min_status) < 0 ||
      static_cast<int>(min_status) > static_cast<int>(GnssFixStatus::kRtkFixed))
    return Bad("min_status", "fix, sbas, rtk_float or rtk_fixed", GnssStatusName(min_status));
  const std::pair<const char*, const GnssStatusNoise*> noises[] = {
      {"fix", &fix}, {"sbas", &sbas}, {"rtk_float", &rtk_float}, {"rtk_fixed", &rtk_fixed}};
  for (const auto& [name, noise] : noises)
    if (Status s = CheckNoise(name, *noise); !s.ok()) return s;
  if (!Positive(offset_correlation_time_s))
    return Bad("offset_correlation_time_s", "> 0", offset_correlation_time_s);
  if (!Positive(integrity_gate)) return Bad("integrity_gate", "> 0", integrity_gate);
  if (!(std::isfinite(prediction_sigma_m) && prediction_sigma_m >= 0))
    return Bad("prediction_sigma_m", "finite and >= 0", prediction_sigma_m);
  if (!(std::isfinite(prediction_drift_fraction) && prediction_drift_fraction >= 0))
    return Bad("prediction_drift_fraction", "finite and >= 0", prediction_drift_fraction);
  if (!(std::isfinite(step_max_hold_s) && step_max_hold_s >= 0))
    return Bad("step_max_hold_s", "finite and >= 0", step_max_hold_s);
  if (!Positive(min_alignment_baseline_m))
    return Bad("min_alignment_baseline_m", "> 0", min_alignment_baseline_m);
  if (min_alignment_fixes < 2) return Bad("min_alignment_fixes", ">= 2", min_alignment_fixes);
  if (!Positive(max_alignment_rms_m)) return Bad("max_alignment_rms_m", "> 0", max_alignment_rms_m);
  if (!Positive(max_interpolation_gap_s))
    return Bad("max_interpolation_gap_s", "> 0", max_interpolation_gap_s);
  if (!(std::isfinite(max_snap_s) && max_snap_s >= 0))
    return Bad("max_snap_s", "finite and >= 0", max_snap_s);
  return {};
}

}  // namespace uf::estimator
