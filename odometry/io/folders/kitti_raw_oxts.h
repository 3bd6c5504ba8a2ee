// One OXTS RT3003 record of a KITTI raw drive (oxts/data/NNNNNNNNNN.txt: 30 numbers, see the drive's
// oxts/dataformat.txt) and what the project makes of it: an IMU sample, a GNSS fix and, for the reference
// trajectory, the INS pose by the KITTI devkit's formula. Internal to uf_io.
#pragma once

#include <filesystem>
#include <string>

#include "odometry/types/measurements.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf {

struct OxtsRecord {
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;
  double roll = 0, pitch = 0, yaw = 0;             // rad; yaw 0 = east, counter-clockwise
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // ax ay az: m/s^2 in the OXTS frame (x fwd, y left, z up)
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // wx wy wz: rad/s in the OXTS frame
  double position_accuracy_m = 0;                  // pos_accuracy: north/east, m
  int navstat = 0, numsats = 0, posmode = 0;
};

// Parses the 30 numbers of one file; errors name the file, the field and the value.
Expected<OxtsRecord> ReadOxtsFile(const std::filesystem::path& path);

// The IMU sample: the OXTS accelerations include gravity (+9.8 m/s^2 up at rest), as the project's IMU
// samples do; KITTI's sync package resamples them to the LiDAR frames (10 Hz).
ImuSample OxtsImuSample(const OxtsRecord& record, Stamp stamp);

// The position as a GNSS fix. The OXTS position is its INS solution (GNSS blended with the IMU), not a raw
// receiver fix. Covariance: pos_accuracy as the east and north sigma (at least 0.02 m), twice it as the up
// sigma (KITTI gives no vertical accuracy; GNSS height is typically 1.5-2x worse than horizontal). Status:
// no fix unless navstat is 4 (locked); then from posmode (OXTS NCOM: 3 SPS -> fix, 4 differential and 7
// SBAS -> sbas, 5 RTK float, 6 RTK integer; other codes, e.g. -1 on KITTI drives, -> fix: the INS position
// stays valid). KITTI's alt is taken as the ellipsoidal height (its dataformat does not say which).
GnssFix OxtsGnssFix(const OxtsRecord& record, Stamp stamp);

// The KITTI devkit's convertOxtsToPose for one record: T_world_oxts with the world a Mercator plane at
// scale = cos(latitude of the drive's first record), x east, y north, z up (the altitude), and
// R = Rz(yaw) Ry(pitch) Rx(roll).
SE3 OxtsMercatorPose(const OxtsRecord& record, double mercator_scale);

}  // namespace uf
