// Readers of dataset folders: KITTI-style LiDAR folders, EuRoC ASL (MAV) folders and the project's own
// format (see ultrafusion_dataset_writer.h for its description). All stream their files: one scan or image
// file, and one line of each CSV, is read per Next() call, so memory stays bounded on long recordings.
#pragma once

#include <filesystem>
#include <memory>

#include "odometry/io/dataset_options.h"
#include "odometry/io/dataset_reader.h"
#include "odometry/types/status.h"

namespace uf {

// A KITTI-style LiDAR folder:
//   velodyne/ (or lidar/)   one scan per file, .bin (KITTI: float32 x y z intensity) or .pcd, in name order
//   times.txt               one stamp per scan, seconds (relative or absolute), parsed exactly to the ns
//   groundtruth*.tum, poses.txt, poses/<folder>.txt or ../../poses/<folder>.txt (KITTI's dataset/ layout):
//                           ground truth, reported in the description
// LidarScan::stamp is the times.txt stamp (for a PCD with relative point times: plus the earliest of them;
// absolute point times in a PCD are kept as they are). Scans without per-point times get azimuth-derived
// ones when options.derive_point_times_from_azimuth (see DerivePointTimesFromAzimuth, also for how KITTI's
// stamps relate to the sweep), and end = stamp + options.lidar_sweep_period_s. Points with NaN/Inf are
// dropped and counted in warnings(); a damaged scan file is an error naming it.
Expected<std::unique_ptr<DatasetReader>> OpenKittiFolder(const std::filesystem::path& path,
                                                         const DatasetOptions& options = {});

// A KITTI raw drive (the "sync" package, rectified images; or "extract", raw images): `path` is the drive
// folder (2011_09_26_drive_0009_sync), its date folder one level up holds calib_imu_to_velo.txt,
// calib_velo_to_cam.txt and calib_cam_to_cam.txt (kitti_raw_calibration.h). Streams, each a <name>/data/
// folder of files named by their 10-digit frame index and a <name>/timestamps.txt (wall-clock times read as
// UTC, line N for frame N):
//   velodyne_points  .bin (float32 x y z reflectance), .bin.xz, or .txt (extract: ASCII) -> LiDAR in the
//                    Velodyne frame; the sweep from timestamps_start/_end.txt when present (else half of
//                    options.lidar_sweep_period_s either side of the timestamps.txt stamp, the instant the
//                    head faced forward); point times from azimuth as for KITTI-style folders
//   oxts             30 numbers per record (kitti_raw_oxts.h) -> an IMU stream (ax ay az, wx wy wz) and a
//                    GNSS stream (lat lon alt, pos_accuracy), both in the OXTS frame = the body; the INS
//                    poses -> DatasetDescription::reference
//   image_00..03     PNG -> camera N (rectified pinhole for sync, K/D for extract); a folder with
//                    timestamps only (no data/) is no stream
// Extrinsics: T_body_sensor with the body = the OXTS IMU. A file whose stamp line is empty (KITTI marks
// lost frames so), frame indices missing between the first and last file, and a damaged scan file are
// counted warnings (the file is skipped); a missing calibration file, a stamp that does not parse, stamps
// that do not increase, a damaged OXTS record and an image of another size than the calibration are errors.
bool IsKittiRawDrive(const std::filesystem::path& path);
Expected<std::unique_ptr<DatasetReader>> OpenKittiRawDrive(const std::filesystem::path& path,
                                                           const DatasetOptions& options = {});

// A EuRoC ASL folder: `path` is the dataset root holding mav0/, or mav0/ itself. Reads
//   mav0/imu0/data.csv      `timestamp [ns], w_RS_S_x, _y, _z [rad s^-1], a_RS_S_x, _y, _z [m s^-2]`
//   mav0/camN/data.csv      `timestamp [ns], filename` with the images in mav0/camN/data/ (camera index N)
//   mav0/<sensor>/sensor.yaml  T_BS (4x4, row-major) -> StreamInfo::T_body_sensor, rate_hz -> nominal_rate_hz
//   mav0/state_groundtruth_estimate0/data.csv -> ground truth
// and merges the streams by stamp. Camera frames carry the PNG bytes (decoded later); a missing image file
// is skipped with a warning.
Expected<std::unique_ptr<DatasetReader>> OpenEurocFolder(const std::filesystem::path& path,
                                                         const DatasetOptions& options = {});

// The project's own format: a folder with dataset.yaml (see ultrafusion_dataset_writer.h).
Expected<std::unique_ptr<DatasetReader>> OpenUltrafusionFolder(const std::filesystem::path& path,
                                                               const DatasetOptions& options = {});

}  // namespace uf
