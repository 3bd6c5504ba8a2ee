// The georeference of a run's map from the run's GNSS fixes (docs/ARCHITECTURE.md, "Frames and time"):
// AlignToGnss (gnss_alignment.h) with the options that follow from the dataset and the estimator:
//  - the lever arm is the antenna in the estimator's body frame,
//      T_estimator_antenna = T_estimator_body * T_body_gnss,
//    T_body_gnss the GNSS stream's T_body_sensor (the antenna at the body origin when the dataset has none);
//  - a gravity-aligned estimator world (LIO: z up) fits yaw and translation only, any other world (LO: the
//    first LiDAR pose) a full rigid transform.
// The result keeps the ENU origin and T_enu_world (the caller turns them into its map's georeference) and a
// note for the run's report: what was found, or why the map is not georeferenced.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "odometry/eval/gnss_alignment.h"
#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/trajectory.h"

namespace uf {

struct GnssGeoreference {
  std::optional<GnssAlignment> alignment;  // origin, T_enu_world, RMS; none: not georeferenced
  std::string note;                        // for the report; empty without fixes
};

// `trajectory`: T_world_body in the estimator's body frame. No fixes: no alignment and no note.
GnssGeoreference GeoreferenceFromGnss(const Trajectory& trajectory, std::span<const GnssFix> fixes,
                                      const std::optional<SE3>& T_body_gnss, const SE3& T_estimator_body,
                                      bool gravity_aligned);

}  // namespace uf
