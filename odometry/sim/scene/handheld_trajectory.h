// The `handheld` motion: a person walks a scene's default path (DefaultScenePath: the path the vehicle
// drives for the same seed) carrying the device, bouncing with the steps and looking around with it. Poses
// T_world_body every 10 ms (100 Hz) from start_stamp; the body is the device's IMU (x forward, y left,
// z up), and it starts at the world origin heading east (+x).
//
//   t < 1 s   standing exactly still (static IMU initialisation), at the path's start.
//   walking   1.3 m/s along the path (DefaultScenePath's quintic ramp over 2 s, +-4 % wobble, period 7 s).
//   Every oscillation below is multiplied by r(t) = S7((t - 1 s) / 2 s), the septic smoothstep
//   S7(u) = 35u^4 - 84u^5 + 70u^6 - 20u^7 (0 -> 1 with zero first, second and third derivatives at both
//   ends): the motion starts with no step in acceleration, angular acceleration or their rates (jerk).
//   position  p(t) = c(t) + r(t) (sway(t) y_c + bounce(t) z), c the path point, y_c its left (horizontal)
//             bounce = A_b sin(phi) + A_2 sin(2 phi + psi)    A_b 2.6-3 cm, A_2 0.3-0.5 cm (heel strike)
//             sway   = A_s sin(phi / 2 + chi)                 A_s 1.5-2.5 cm, at half the step frequency
//             phi    = 2 pi f_step (t - 1 s) + phi_0          f_step 1.8-2 Hz (a step every ~0.7 m)
//   attitude  R(t) = Rz(heading_c(t) + k r yaw(t)) Ry(k r pitch(t)) Rx(k r roll(t))   (x forward, z up)
//             yaw, pitch, roll: sums of three sinusoids with random phases, at frequencies drawn in
//             [0.1, 0.2] Hz (looking around), [0.4, 0.8] and [0.9, 1.5] Hz (quick turns of the wrist), of
//             amplitudes 38, 3, 5 deg (yaw about the path's heading), 12, 3, 4 (pitch), 8, 2, 3 (roll).
//             k scales them so that the peak body rate over the whole sequence is kHandheldPeakRateDegS:
//             fixed-point iterations k <- k * target / peak(k) on the central differences
//             |Log(R_{i-1}^T R_{i+1})| / 20 ms of the 10 ms poses (the path's turns included), k in [0.25,
//             2]. A sequence shorter than ~6 s may stay below the target (k is capped).
//   Over 20 s (30 draws, five scenes): k 0.8-1.25, yaw within +-35-56 deg, tilt of the body's z axis up to
//   15-26 deg, and 25-37 deg (mean 32) and 0.68 m at most between poses 0.5 s apart (2 Hz scans): the
//   largest rotation over 0.5 s is about a third of the peak rate times 1 s whatever the amplitudes, so
//   the target is 95 deg/s, not more.
// Every quantity is drawn from SubSeed(seed, "handheld/" + scene), so the path is the vehicle's whatever
// the motion and the handheld draws do not move it.
#pragma once

#include <cstdint>
#include <string_view>

#include "odometry/sim/scene/default_trajectory.h"

namespace uf::sim {

inline constexpr double kHandheldPeakRateDegS = 95.0;  // the peak body rate the look-around is scaled to
inline constexpr double kWalkingSpeed = 1.3;           // m/s

struct HandheldTrajectory {
  Trajectory poses;  // the device, T_world_body every 10 ms
  // The walker's path at the device's mean height (yaw = heading, no bounce, sway or look-around), on the
  // same stamps: what the scene is laid out along (its ground lies body_height_m below it).
  Trajectory path;
  double look_scale = 1.0;     // k
  double peak_rate_rad_s = 0;  // the peak body rate of `poses` by central differences, after scaling
};

// The errors of DefaultSceneTrajectory (unknown scene, duration_s not in [2, 7200]).
Expected<HandheldTrajectory> HandheldSceneTrajectory(std::string_view scene, double duration_s,
                                                     std::uint64_t seed, Stamp start_stamp);

}  // namespace uf::sim
