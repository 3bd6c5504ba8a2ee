#include "viewer/pipeline/stages/odometry_stage.h"

#include <deque>

#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"
#include "viewer/pipeline/stages/odometry_files.h"
#include "viewer/pipeline/track/track_overlay.h"

namespace uf::pipeline {
namespace {

constexpr std::int64_t kMaxKeptDecodeErrors = 5;  // undecodable frames whose reason is kept as a warning
constexpr std::size_t kWarningsInFailure = 3;     // warnings quoted when the odometry produced no pose

// Moves the keyframes that left the odometry's window into the trajectory (and the mapper), in time order.
Status CollectFinished(const OdometryStageInput& in, OdometryStageOutput& out, OdometryCollected& collected,
                       std::int64_t& keyframes) {
  for (Keyframe& k : in.odometry->TakeFinished()) {
    ++keyframes;
    if (!collected.pose_stamps.empty() && k.stamp <= collected.pose_stamps.back())
      continue;  // keep stamps increasing
    collected.pose_stamps.push_back(k.stamp);
    collected.poses.push_back(k.T_world_body);
    if (k.inertial)
      collected.imu_states.push_back({k.stamp, k.velocity, k.bias_acc, k.bias_gyro, k.lidar_translation});
    if (k.lidar_degeneracy || k.wheel_consistency || !k.gnss_checks.empty() || k.imu_reliability ||
        !k.camera_checks.empty())
      collected.scored.push_back({k.stamp, k.lidar_degeneracy, k.wheel_consistency, k.gnss_checks,
                                  k.imu_reliability, k.camera_checks});
    if (in.frames.mode == OdometryMode::kWio) {
      const std::optional<Georeference> georef = in.odometry->georeference();
      collected.T_enu_world_at_pose.push_back(georef ? std::optional<SE3>(georef->T_enu_world)
                                                     : std::nullopt);
    }
    if (in.mapper) {
      if (Status s = in.mapper->AddKeyframe(std::move(k)); !s.ok()) return s;
      ++out.keyframes_mapped;
    }
  }
  for (const StepTime& step : in.odometry->TakeStepTimes()) {
    collected.stamps.push_back(step.stamp);
    collected.ms.push_back(step.ms);
    if (step.stages) {
      if (!collected.stage_sums) collected.stage_sums.emplace();
      *collected.stage_sums += *step.stages;
    }
    if (step.landmarks >= 0) collected.visual.push_back(step);
  }
  for (estimator::TrackEvent& event : in.odometry->TakeEvents())
    out.summary.track_events.push_back(std::move(event));
  return {};
}

// run --calibrate-online, once the rotation has locked: the window moves to the new extrinsic keeping its
// LiDAR poses (RunEstimator::SetLidarExtrinsic), and so do the poses that had left it, T_world_E * delta with
// delta = T_E_lidar_old T_E_lidar_new^-1; the frames take the new extrinsic (written to run.json). A window
// that refuses it (GNSS factors) runs on with the given one; the report says why.
void ApplyLockedExtrinsic(CalibrationBranch& calibration, Stamp stamp, RunEstimator& odometry,
                          OdometryStageOutput& out, OdometryCollected& collected) {
  const std::optional<SE3> T_imu_lidar = calibration.ExtrinsicToApply();
  if (!T_imu_lidar) return;
  const Status status = odometry.SetLidarExtrinsic(*T_imu_lidar);
  calibration.Applied(stamp, status);
  if (!status.ok()) return;
  const SE3 delta = out.frames.T_estimator_lidar() * T_imu_lidar->inverse();
  for (SE3& pose : collected.poses) pose = pose * delta;
  out.frames.SetImuFromLidar(*T_imu_lidar);
}

// The front end's statistics of a frame, and its overlay when it is an overlay_every-th one.
Status KeepTracked(const OdometryStageInput& in, std::vector<estimator::TrackedFrame> tracked,
                   const Image& image, OdometryStageOutput& out) {
  for (estimator::TrackedFrame& frame : tracked) {
    const std::size_t index = out.tracked_frames.size();
    out.tracked_frames.push_back(frame.stats);
    if (in.overlay_every <= 0 || index % static_cast<std::size_t>(in.overlay_every) != 0) continue;
    Expected<std::vector<std::uint8_t>> png =
        EncodePng(RenderTrackOverlay(image, frame, in.min_track_length), "track overlay");
    if (!png) return png.status();
    out.overlays.emplace_back(frame.stamp, std::move(*png));
  }
  return {};
}

}  // namespace

int PacedStream(const DatasetSensors& sensors, OdometryMode mode) {
  return mode == OdometryMode::kWio ? sensors.imu : sensors.lidar;
}

Expected<OdometryStageOutput> RunOdometryStage(const OdometryStageInput& in, StageContext& context) {
  OdometryStageOutput out;
  out.frames = in.frames;
  OdometryCollected collected;
  std::int64_t scans = 0, keyframes = 0, paced = 0;
  const DatasetSensors& sensors = in.sensors;
  RunEstimator& odometry = *in.odometry;
  const int paced_stream = PacedStream(sensors, in.frames.mode);
  const bool lidar_window = in.frames.mode != OdometryMode::kWio;  // WIO reads no scan
  context.SetUnit(paced_stream == sensors.lidar ? "scans" : "IMU samples");
  // Decodes a frame for the estimator; one that cannot be decoded is a kept warning, and skipped.
  auto decode = [&](CameraFrame& frame, const std::string& what) {
    const Status decoded = DecodeCameraFrame(frame);
    if (!decoded.ok() && ++out.camera_undecodable <= kMaxKeptDecodeErrors)
      collected.camera_warnings.push_back(what + " at " + StampText(frame.stamp) + ": " + decoded.message() +
                                          "; skipped");
    return decoded.ok();
  };
  // One measurement to the estimator (or the mapper): as read, or when the calibration's hold ends.
  auto feed = [&](Measurement& m) {
    if (m.stream == paced_stream) ++paced;
    Status status;
    if (auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == sensors.lidar && lidar_window) {
      ++scans;
      if (in.calibration) {
        ApplyLockedExtrinsic(*in.calibration, scan->stamp, odometry, out, collected);
        if (!in.calibration->Restamp(*scan)) return Status();  // re-stamped behind the previous scan
      }
      if (in.point_time_recheck) {
        in.point_time_recheck->Notice(out.summary.track_events);
        if (Status s = in.point_time_recheck->Prepare(*scan); !s.ok()) return s;
      }
      status = odometry.AddScan(*scan);
    } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == sensors.imu) {
      status = odometry.AddImu(*sample);
    } else if (const auto* wheel = std::get_if<WheelSample>(&m.data); wheel && m.stream == sensors.wheel) {
      status = odometry.AddWheel(*wheel);
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data);
               frame && in.camera_factors && m.stream == sensors.camera) {
      if (!decode(*frame, "frame")) return Status();
      status = odometry.AddCameraFrame(*frame);
      if (status.ok()) status = KeepTracked(in, odometry.TakeTrackedFrames(), frame->image, out);
      if (in.mapper && in.mapper->UsesCamera(m.stream))
        in.mapper->AddCameraFrame(m.stream, std::move(*frame));
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data); frame && m.stream == in.stereo_stream) {
      if (!decode(*frame, "right frame")) return Status();
      status = odometry.AddRightCameraFrame(*frame);
      if (in.mapper && in.mapper->UsesCamera(m.stream))
        in.mapper->AddCameraFrame(m.stream, std::move(*frame));
    } else if (auto* frame = std::get_if<CameraFrame>(&m.data);
               frame && in.mapper && in.mapper->UsesCamera(m.stream)) {
      in.mapper->AddCameraFrame(m.stream, std::move(*frame));
      return Status();
    } else if (const auto* fix = std::get_if<GnssFix>(&m.data); fix && m.stream == sensors.gnss) {
      out.fixes.push_back(*fix);
      if (!in.gnss_factors) return Status();
      status = odometry.AddGnss(*fix);
    } else {
      return Status();
    }
    if (status.ok()) status = CollectFinished(in, out, collected, keyframes);
    if (status.ok()) context.Progress(paced, in.paced_messages);
    return status;
  };
  // run --calibrate-online: the branch sees every scan and IMU sample as read; the rest waits while the
  // branch holds the run for the locks (CalibrationBranch::Holds).
  std::deque<Measurement> held;
  auto release = [&] {
    for (; !held.empty(); held.pop_front())
      if (Status s = feed(held.front()); !s.ok()) return s;
    return Status();
  };
  const Status read = ForEachMeasurement(*in.stream, [&](Measurement& m) {
    if (!in.calibration) return feed(m);
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == sensors.lidar) {
      if (Status s = in.calibration->AddScan(*scan); !s.ok()) return s;
    } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == sensors.imu) {
      in.calibration->AddImu(*sample);
    }
    if (in.calibration->Holds(StampOf(m.data))) {
      held.push_back(std::move(m));
      return Status();
    }
    if (Status s = release(); !s.ok()) return s;
    return feed(m);
  });
  if (!read.ok()) return read;
  if (Status s = release(); !s.ok()) return s;
  odometry.Finish();
  if (Status s = CollectFinished(in, out, collected, keyframes); !s.ok()) return s;
  out.estimated = {std::move(collected.pose_stamps).TakeVector(), std::move(collected.poses).TakeVector()};
  if (in.point_time_recheck) {
    in.point_time_recheck->Finish();
    out.summary.point_time_recheck = in.point_time_recheck->result();
  }
  if (in.calibration) {  // after the window's last poses, which may still be from before the lock
    in.calibration->Finish();
    out.summary.online_calibration = in.calibration->summary();
    RestampEarlierPoses(out.estimated, in.calibration->summary());
    out.summary.calibration_estimates = in.calibration->result();
    Expected<std::vector<std::string>> written = WriteCalibrateOutputs(in.out, in.calibration->result());
    if (!written) return written.status();
    for (const std::string& file : *written) context.AddOutput(file);
  }

  OdometrySummary& summary = out.summary;
  summary.step = odometry.step();
  summary.initialization = odometry.initialization();
  summary.scans = scans;
  summary.keyframes = static_cast<std::int64_t>(out.estimated.size());
  summary.skipped = summary.step == "scan" ? scans - keyframes : 0;  // WIO nodes are not skipped
  summary.timing = SummarizeTimings({collected.ms.begin(), collected.ms.end()});
  if (collected.stage_sums)
    summary.stage_means = *collected.stage_sums / static_cast<double>(collected.ms.size());
  summary.reader_warnings = in.stream->warnings();
  summary.odometry_warnings = odometry.warnings();
  for (std::string& warning : collected.camera_warnings)
    summary.odometry_warnings.push_back(std::move(warning));
  if (out.camera_undecodable > kMaxKeptDecodeErrors)
    summary.odometry_warnings.push_back(std::to_string(out.camera_undecodable) +
                                        " camera frames failed to decode in all (the first " +
                                        std::to_string(kMaxKeptDecodeErrors) + " are listed)");
  summary.sensor_factors = odometry.sensor_factors();
  out.georef = odometry.georeference();
  // trajectory.tum's world W is ENU now; the map stays in the estimator's: T_M_W = T_M_world T_world_enu.
  if (out.georef) out.frames.T_map_world = in.frames.T_map_world * out.georef->T_enu_world.inverse();
  if (out.estimated.empty()) {
    // The report of a failed stage has no warnings section: the reasons go into the message.
    std::string reasons;
    for (std::size_t i = 0; i < summary.odometry_warnings.size() && i < kWarningsInFailure; ++i)
      reasons += (i == 0 ? ": " : "; ") + summary.odometry_warnings[i];
    return Status::Error(in.stream->description().path.string() + ": the odometry produced no pose (" +
                         std::to_string(collected.ms.size()) + " " + summary.step + "s, " +
                         std::to_string(summary.odometry_warnings.size()) + " warnings" + reasons + ")");
  }
  if (Status s = WriteOdometryFiles(in, out, collected, summary, context); !s.ok()) return s;
  return out;
}

}  // namespace uf::pipeline
