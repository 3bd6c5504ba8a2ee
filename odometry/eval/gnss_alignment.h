// Georeferencing a trajectory (and the map built along it) with GNSS fixes, until the estimator has its own
// GNSS factor (docs/METHOD.md, "Not implemented yet"): the rigid transform T_enu_world that best maps the
// trajectory's antenna positions onto the fixes, in an east-north-up frame (odometry/types/geodetic.h) at
// the first usable fix.
//
// With fixes f_i (ENU, weight w_i = 1 / (mean variance of its covariance)) and the antenna positions
// a_i = T_world_body(t_i) * p_body_antenna (trajectory interpolated at the fix time), minimise
//   sum_i w_i |T a_i - f_i|^2
// over T = (R, t) with uf::WeightedRigidAlignment (odometry/types/alignment.h): weighted Umeyama in 3D, or,
// for a gravity-aligned world (LIO: z is up in both frames), the yaw and the translation only. Fixes without
// a position (no fix) or outside the trajectory's time span are not used. The result is admitted only with
// enough fixes spread over enough distance (else the heading is not determined) and a residual RMS below
// max_rms_m.
#pragma once

#include <span>

#include "odometry/types/geodetic.h"
#include "odometry/types/measurements.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

struct GnssAlignmentOptions {
  SE3 T_body_antenna;           // antenna in the trajectory's body frame (lever arm)
  bool gravity_aligned = true;  // estimate yaw + translation only (the world's z is up)
  int min_fixes = 10;
  double min_extent_m = 20;  // the used antenna positions must span at least this (largest distance)
  double max_rms_m = 10;     // residual RMS above this: not admitted (wrong data or a broken trajectory)
};

struct GnssAlignment {
  GeodeticOrigin origin;  // of the ENU frame: the first usable fix
  SE3 T_enu_world;        // p_enu = T_enu_world p_world
  double rms_m = 0;       // residual RMS of the used fixes, m
  int fixes_used = 0;
};

// Errors say why no alignment was admitted (no fix with a position, an invalid first fix, too few fixes,
// too little extent, RMS too large).
Expected<GnssAlignment> AlignToGnss(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                    const GnssAlignmentOptions& options = {});

}  // namespace uf
