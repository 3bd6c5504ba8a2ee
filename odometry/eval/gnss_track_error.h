// A trajectory against the GNSS fixes of the same recording, for data without ground truth: the fixes are
// then the only absolute reference, with their own noise (the figures include it: a trajectory can look no
// better than the fixes' sigma).
//
// The antenna positions a_i = T(t_i) l (the trajectory interpolated at each fix time t_i, l the lever arm in
// the trajectory's frame) against the fixes f_i in ENU at `origin`:
//  - a georeferenced trajectory (already in ENU at `origin`): e_i = a_i - f_i, no alignment;
//  - otherwise the trajectory is first fitted to the fixes by AlignToGnss (gnss_alignment.h: yaw and
//    translation for a gravity-aligned world, else a rigid transform; origin = the first fix).
// Figures: horizontal and vertical RMSE of e_i; the track length (horizontal, along the fixes); and the
// relative horizontal error over segments of `segment_m` of track: for each fix i, j the first fix with
// track(i, j) >= segment_m, |(a_j - a_i) - (f_j - f_i)|_h / track(i, j) (after the fit's rotation), mean
// in percent. Its floor from the fixes' own noise is about sqrt(2) sigma_h / segment_m.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "odometry/types/geodetic.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

struct GnssTrackError {
  bool aligned = false;  // fitted by AlignToGnss (false: the trajectory's own georeference)
  int fixes = 0;         // fixes inside the trajectory's time span
  double horizontal_rmse_m = 0, vertical_rmse_m = 0;
  double track_length_m = 0;
  double segment_m = 100;
  std::optional<double> segment_error_percent;  // none when the track is shorter than one segment
  // The pairs compared, ENU at the origin, and each pair's horizontal error (for plots).
  std::vector<Eigen::Vector3d> antenna_enu, fixes_enu;
  std::vector<double> horizontal_error_m;
};

// `georeferenced_origin`: the trajectory's ENU origin when it is georeferenced. Errors: no fix with a
// position in the trajectory's span, or the fit's (AlignToGnss).
Expected<GnssTrackError> CompareWithGnssTrack(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                              const SE3& T_frame_antenna,
                                              const std::optional<GeodeticOrigin>& georeferenced_origin,
                                              bool gravity_aligned, double segment_m = 100);

}  // namespace uf
