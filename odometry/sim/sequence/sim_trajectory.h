// The ground-truth motion of a simulated sequence: the scene's default trajectory (driven, or carried by
// hand: config.trajectory.motion) or a recorded one (TUM, EuRoC or KITTI pose file), resampled into a C2
// spline so that the IMU sees continuous acceleration. Every sensor is simulated from this one spline, and
// groundtruth.tum samples it.
//
// Frames: the simulator's world is z-up and its body frame x forward, y left, z up. TUM and EuRoC files are
// taken to be in that convention already. KITTI pose files are in the KITTI camera convention (x right,
// y down, z forward) for both the world and the moving frame, so they are converted:
//   T_world_body = C T_kitti C^T,  C = [[0, 0, 1], [-1, 0, 0], [0, -1, 0]]   (body axes from camera axes)
// and, having no stamps, get start_stamp + k / kitti_rate_hz.
#pragma once

#include "odometry/sim/sequence/simulation_config.h"
#include "odometry/sim/trajectory_spline.h"
#include "odometry/types/trajectory.h"

namespace uf::sim {

struct SimulationTrajectory {
  Trajectory poses;  // the samples the spline was fitted to
  // What the scene is laid out along (its ground lies body_height_m below it): `poses`, or for the
  // handheld motion the walker's path without bounce, sway and look-around.
  Trajectory scene_path;
  TrajectorySpline spline;   // T_world_body(t)
  Stamp begin = 0, end = 0;  // the simulated span: first and last pose stamp
  // How closely the spline follows `poses`: the largest position and rotation differences at their stamps.
  double fit_position_error_m = 0.0, fit_rotation_error_rad = 0.0;
};

// Fails with a message naming the file for an unreadable file, fewer than 4 poses (after cutting to
// duration_s), bad stamps or poses the spline cannot follow.
Expected<SimulationTrajectory> MakeSimulationTrajectory(const SimulationConfig& config);

}  // namespace uf::sim
