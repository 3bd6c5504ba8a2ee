// The frames of one run, typed: which body the estimator tracks, which frame trajectory.tum is written in,
// where the map's world sits, and every transform between them. `run` resolves them once from the dataset's
// calibration (ResolveRunFrames), writes them to run.json (run_record.h), and `splat` reads them back from
// there instead of working them out again. The names and conventions are those of docs/ARCHITECTURE.md
// ("Frames and time"): T_a_b maps points of frame b into frame a.
//
//   B  the dataset's body (its IMU unless the IMU stream says otherwise; StreamInfo::T_body_sensor)
//   E  the estimator's body: the LiDAR in LO, the IMU in LIO and WIO
//   F  the frame of trajectory.tum (--output-frame): the LiDAR or the IMU
//   W  the world of trajectory.tum;  M  the world of the map (map.vdb)
//
// trajectory.tum holds T_W_F(t), made from the estimator's T_world_E(t) by OutputTrajectory. The map is in
// the estimator's world, which is W except for an LO run written in the IMU frame, whose world ToImuFrame
// moves to the first IMU pose (T_M_W = T_imu_lidar^-1 there; identity when the map was remade from
// trajectory.tum by `run --from map`, which keeps W).
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include "odometry/io/dataset_reader.h"
#include "odometry/types/trajectory.h"

namespace uf::pipeline {

enum class OdometryMode { kLo, kLio, kWio };      // LiDAR only; LiDAR + IMU; wheel + IMU (no LiDAR)
enum class TrajectoryFrame { kLidar, kImu };      // frame F of trajectory.tum
enum class MapSource { kOdometry, kTrajectory };  // keyframes of the odometry; trajectory.tum (--from map)

// "lo" / "lio" / "wio", "lidar" / "imu", "odometry" / "trajectory": the words of run.json.
std::string_view Name(OdometryMode mode);
std::string_view Name(TrajectoryFrame frame);
std::string_view Name(MapSource source);
std::optional<OdometryMode> ParseOdometryMode(std::string_view text);
std::optional<TrajectoryFrame> ParseTrajectoryFrame(std::string_view text);
std::optional<MapSource> ParseMapSource(std::string_view text);

// The frame the estimator's body is: the LiDAR in LO, the IMU in LIO and WIO.
TrajectoryFrame EstimatorFrame(OdometryMode mode);

struct RunFrames {
  OdometryMode mode = OdometryMode::kLo;
  TrajectoryFrame trajectory_frame = TrajectoryFrame::kLidar;
  MapSource map_from = MapSource::kOdometry;
  std::optional<SE3> T_imu_lidar;  // from the dataset (ImuFromSensor); needed whenever F != E (and in LIO)
  SE3 T_estimator_body;            // T_E_B
  SE3 T_output_body;               // T_F_B
  SE3 T_map_world;                 // T_M_W

  // T_E_lidar: identity in LO, T_imu_lidar in LIO (WIO, which reads no LiDAR: identity).
  SE3 T_estimator_lidar() const;
  // T_F_E: identity when F is E, else T_imu_lidar or its inverse.
  SE3 T_output_estimator() const;
  // The odometry's trajectory T_world_E(t) as trajectory.tum holds it: unchanged when F is E; an LO
  // trajectory in the IMU frame is ToImuFrame'd (world moved to the first IMU pose), an LIO one in the LiDAR
  // frame ToLidarFrame'd (same world).
  Trajectory OutputTrajectory(const Trajectory& estimated) const;
  // LIO: the LiDAR's extrinsic replaced by `T` (run --calibrate-online applied a locked rotation); the
  // output frame follows when it is the LiDAR.
  void SetImuFromLidar(const SE3& T);
};

// Resolves every transform from the dataset's calibration for a run in `mode` writing `trajectory_frame`.
// Errors: F != E without T_imu_lidar, LO or LIO on a dataset without a LiDAR stream.
Expected<RunFrames> ResolveRunFrames(const DatasetDescription& description, OdometryMode mode,
                                     TrajectoryFrame trajectory_frame, MapSource map_from);

}  // namespace uf::pipeline
