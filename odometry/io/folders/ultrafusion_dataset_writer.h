// Writer of the project's own dataset format (the simulator's output; OpenUltrafusionFolder reads it).
//
// # The ultrafusion dataset format, version 1
//
// A folder holding `dataset.yaml` and one file per stream. Stamps are integer nanoseconds everywhere
// (since the epoch or since the start of the recording); units are SI; each measurement is expressed in its
// own sensor's frame, as the uf::measurement structs define.
//
//   dataset.yaml
//     format: ultrafusion-dataset
//     version: 1
//     streams:                       # in stream index order
//       - name: imu                  # free text, unique (e.g. the topic it was recorded from)
//         kind: imu                  # imu | lidar | camera | wheel | gnss
//         file: imu.csv              # relative to the folder
//         camera: 0                  # camera streams only: index of the camera in the rig
//         rate_hz: 200               # optional nominal rate
//         T_body_sensor: [16 numbers]  # optional 4x4 transform, row-major, last row 0 0 0 1
//         calibration:               # optional, camera streams: intrinsics (camera_calibration.h)
//           distortion_model: radial-tangential     # or equidistant
//           intrinsics: [fx, fy, cx, cy]
//           distortion_coefficients: [k1, k2, p1, p2, k3]   # equidistant: [k1, k2, k3, k4]
//           resolution: [width, height]
//     ground_truth: groundtruth.tum  # optional
//     ground_truth_enu_origin:       # optional: the ground truth's world is ENU at this WGS84 point
//       {latitude_deg: 49.0069, longitude_deg: 8.4037, height_m: 115}
//   Unknown keys are an error.
//
//   imu.csv      # stamp_ns,gx,gy,gz,ax,ay,az
//                angular velocity (rad/s), then specific force (m/s^2, +g up at rest), IMU frame
//   wheel.csv    # stamp_ns,vx,vy,vz,wx,wy,wz
//                linear (m/s), then angular (rad/s) velocity, wheel/base frame
//   gnss.csv     # stamp_ns,latitude_deg,longitude_deg,altitude_m,c00,c01,c02,c10,c11,c12,c20,c21,c22,status
//                WGS84, altitude above the ellipsoid; ENU position covariance row-major (m^2);
//                status: no_fix | fix | sbas | rtk_float | rtk_fixed
//   camN/camN.csv  # stamp_ns,filename     with the image files (PNG or JPEG) beside it: camN/<stamp_ns>.png
//   lidar.bin    scan records, little-endian, appended (byte layout in lidar_record_file.h):
//                "UFLS", flags u32, stamp_ns i64, end_ns i64, point_count u64, then per point
//                x y z intensity f32, ring u16, offset_ns i32 (22 bytes)
//   groundtruth.tum  `t x y z qx qy qz qw`, t in seconds with nine decimals (exact nanoseconds)
//
// CSV files start with one '#' header line; numbers are written in the shortest form that reads back to
// the same double, so a written dataset reads back bit-exact. Within a file stamps increase strictly.
// A second stream of a kind gets a numbered file (imu1.csv, lidar1.bin).
//
// Atomicity: stream files are written under temporary names and renamed by Finish(), which writes
// dataset.yaml last; a folder without dataset.yaml is not a dataset, so an interrupted write never leaves
// one that reads as complete. Create() refuses a folder that already holds a dataset.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "odometry/io/dataset_reader.h"
#include "odometry/io/measurement.h"
#include "odometry/types/geodetic.h"
#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf {

class UltrafusionDatasetWriter {
 public:
  // Starts a dataset in `folder` (created if needed) with these streams; Measurement::stream indexes them.
  // Uses each StreamInfo's name, kind, camera (-1: numbered in order), T_body_sensor, camera_model and
  // nominal_rate_hz.
  static Expected<UltrafusionDatasetWriter> Create(const std::filesystem::path& folder,
                                                   std::vector<StreamInfo> streams);

  UltrafusionDatasetWriter(UltrafusionDatasetWriter&&) noexcept;
  UltrafusionDatasetWriter& operator=(UltrafusionDatasetWriter&&) noexcept;
  ~UltrafusionDatasetWriter();  // without Finish(): removes the temporary files, leaves no dataset

  // Appends one measurement to its stream's file. The kind must match the stream's and stamps must
  // increase within a stream. Camera frames are written from their PNG/JPEG bytes, or encoded to PNG from
  // the decoded image when they have none.
  Status Write(const Measurement& measurement);

  // Writes groundtruth.tum (the trajectory needs stamps).
  // enu_origin: when the trajectory's world is ENU at that point (the simulator's), dataset.yaml says so.
  Status WriteGroundTruth(const Trajectory& trajectory, const std::optional<GeodeticOrigin>& enu_origin = {});

  // Renames the stream files into place and writes dataset.yaml. Nothing can be written afterwards.
  Status Finish();

 private:
  struct State;
  explicit UltrafusionDatasetWriter(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace uf
