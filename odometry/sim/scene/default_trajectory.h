// Default body trajectories for the simulator's scenes: smooth, seeded, analytic motions that a C2 spline
// (TrajectorySpline::FitPoses, knots every ~0.1 s) follows closely.
//
// Poses T_world_body every 10 ms (100 Hz) from start_stamp for duration_s; body frame x forward (along the
// velocity), y left, z up; the body starts at the world origin heading east (+x). The motion stands still
// for the first second, then the speed ramps up to cruise with the quintic smoothstep
// S(u) = 6u^5 - 15u^4 + 10u^3 (zero velocity, acceleration and jerk at both ends). The track is integrated
// from an analytic curvature kappa(s) (sums of sin^2 turns and zero-net-heading lane changes) and an
// analytic height z(s) (slow sinusoids); the attitude is yaw = heading, pitch = -atan(dz/ds) (grade) plus
// squat and suspension oscillations of ~1 Hz, roll = lean in turns plus oscillations, all scaled by v /
// v_cruise so that the standing second is exactly still.
//   urban: ~8 m/s car, gentle curves and lane changes; wild: ~3 m/s rough-terrain robot, tighter curves,
//   hills, several degrees of roll/pitch; warehouse: 1.5 m/s robot serpentining through aisles (smooth
//   90-degree turns); corridor: 1.2 m/s, nearly straight; tunnel: ~12 m/s car, nearly straight.
// This is the `vehicle` motion; the `handheld` one (handheld_trajectory.h) walks the same path.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "odometry/types/stamp.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::sim {

// Errors: unknown scene (the message lists SceneNames()), duration_s not in [2, 7200].
Expected<Trajectory> DefaultSceneTrajectory(std::string_view scene, double duration_s, std::uint64_t seed,
                                            Stamp start_stamp);

// The cruise speed (m/s) of a scene's default trajectory; 0 for an unknown scene.
double DefaultCruiseSpeed(std::string_view scene);

// How the body moves along a scene's default path: driven by a vehicle (DefaultSceneTrajectory) or carried
// by a walking person (HandheldSceneTrajectory, handheld_trajectory.h).
enum class Motion { kVehicle, kHandheld };
std::string_view MotionName(Motion motion);  // "vehicle", "handheld"
const std::vector<std::string_view>& MotionNames();
// Errors name the value and list MotionNames().
Expected<Motion> ParseMotion(std::string_view name);

// The speed along the path after the standing second: cruise_m_s * S(u) * (1 + wobble sin(2 pi tau /
// wobble_period_s)), S the quintic smoothstep, u = tau / ramp_s, tau = t - 1 s.
struct PathSpeed {
  double cruise_m_s = 1.0;
  double ramp_s = 2.0;
  double wobble = 0.0;
  double wobble_period_s = 10.0;
};

// A scene's default path, the one DefaultSceneTrajectory drives for the same seed (the same curvature and
// heights over arc length), travelled at `speed` instead: poses every 10 ms from start_stamp for
// duration_s with yaw = the path's heading, no pitch or roll, z = the path's height (the body height above
// its ground). The errors of DefaultSceneTrajectory.
Expected<Trajectory> DefaultScenePath(std::string_view scene, double duration_s, std::uint64_t seed,
                                      Stamp start_stamp, const PathSpeed& speed);

}  // namespace uf::sim
