#include "viewer/pipeline/calibrate/calibrate_job.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "odometry/eval/series_plot.h"
#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_sensors.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/measurement_stream.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/calibrate/calibration_branch.h"
#include "viewer/pipeline/point_time_selection.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;
using estimator::CalibrationSolve;
using estimator::CalibrationWorker;

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// "a LiDAR stream" / "an IMU stream" is what calibrate needs; names the streams the dataset has.
Status MissingSensor(const fs::path& dataset, const DatasetDescription& d, const char* what) {
  std::string has;
  for (const StreamInfo& s : d.streams)
    has += (has.empty() ? "" : ", ") + s.name + " (" + std::string(SensorKindName(s.kind)) + ")";
  return Status::Error(dataset.string() + ": calibrate needs " + what + "; the dataset has " +
                       (has.empty() ? "no streams" : has));
}

std::string SolvesCsv(const CalibrateResult& r) {
  std::ostringstream csv;
  csv << "stamp_ns,worker,accepted,time_offset_s,rotation_x_rad,rotation_y_rad,rotation_z_rad,quality,"
         "residual_rad_s,sigma_deg,locked,reason\n";
  for (const CalibrationSolve& s : r.solves) {
    const Eigen::Vector3d phi = s.R_imu_lidar.Log();
    csv << s.stamp << ',' << (s.worker == CalibrationWorker::kTimeOffset ? "time_offset" : "rotation") << ','
        << (s.accepted ? 1 : 0) << ',' << PrintfText("%.6f", s.time_offset_s) << ','
        << PrintfText("%.6f", phi.x()) << ',' << PrintfText("%.6f", phi.y()) << ','
        << PrintfText("%.6f", phi.z()) << ',' << PrintfText("%.4f", s.quality) << ','
        << PrintfText("%.5f", s.rms_rad_s) << ',' << PrintfText("%.4f", s.sigma_deg) << ','
        << (s.locked ? 1 : 0) << ",\"" << s.reason << "\"\n";
  }
  return csv.str();
}

// The accepted candidates of one worker over time (from the first LiDAR pose), with the locked value:
// the time offset in ms, the rotation as its angle from the given extrinsic's rotation in degrees.
// Returns whether it wrote one (none without accepted candidates).
Expected<bool> WriteWorkerPlot(const fs::path& png, const CalibrateResult& r, CalibrationWorker worker) {
  const bool time = worker == CalibrationWorker::kTimeOffset;
  const SO3 given = r.T_imu_lidar_given ? r.T_imu_lidar_given->so3() : SO3();
  auto value = [&](double offset_s, const SO3& R) {
    return time ? 1e3 * offset_s : (given.inverse() * R).angle() / kDegree;
  };
  std::vector<double> seconds, values;
  for (const CalibrationSolve& s : r.solves) {
    if (s.worker != worker || !s.accepted) continue;
    seconds.push_back(ToSeconds(s.stamp - r.first_pose));
    values.push_back(value(s.time_offset_s, s.R_imu_lidar));
  }
  if (values.empty()) return false;
  std::optional<SeriesLevel> locked;
  if (time && r.time_offset_locked) locked = SeriesLevel{value(*r.time_offset_s, SO3()), "locked"};
  if (!time && r.rotation_locked) locked = SeriesLevel{value(0, *r.R_imu_lidar), "locked"};
  if (Status s = WriteSeriesPlot(
          png.string(), seconds, values, "accepted candidates", locked,
          time ? "LiDAR-IMU time offset" : "LiDAR-IMU rotation", "time from the first LiDAR pose [s]",
          time ? "offset added to the LiDAR stamps [ms]" : "angle from the given rotation [deg]");
      !s.ok())
    return s;
  return true;
}

}  // namespace

double CalibrateResult::LidarTimeOffset() const {
  return ToSeconds(lidar_offset_read - imu_offset_read) + time_offset_s.value_or(0.0);
}

bool CalibrateResult::UsesEstimatedRotation() const {
  if (!R_imu_lidar) return false;
  if (rotation_locked || !T_imu_lidar_given) return true;
  return RotationFromGivenDeg() > 3.0 * LatestRotationSigmaDeg();
}

double CalibrateResult::RotationFromGivenDeg() const {
  if (!R_imu_lidar) return 0.0;
  return ((T_imu_lidar_given ? T_imu_lidar_given->so3() : SO3()).inverse() * *R_imu_lidar).angle() / kDegree;
}

double CalibrateResult::LatestRotationSigmaDeg() const {
  double sigma_deg = 0;
  for (const CalibrationSolve& s : solves)
    if (s.worker == CalibrationWorker::kRotation && s.accepted) sigma_deg = s.sigma_deg;
  return sigma_deg;
}

std::string CalibrateResult::LastRefusal(CalibrationWorker worker) const {
  std::string reason;
  for (const CalibrationSolve& s : solves)
    if (s.worker == worker && !s.accepted) reason = s.reason;
  return reason;
}

std::optional<SE3> CalibrateResult::TImuLidar() const {
  if (!T_imu_lidar_given) {
    if (!R_imu_lidar) return std::nullopt;
    return SE3(*R_imu_lidar, Eigen::Vector3d::Zero());
  }
  return SE3(UsesEstimatedRotation() ? *R_imu_lidar : T_imu_lidar_given->so3(),
             T_imu_lidar_given->translation());
}

Expected<CalibrateResult> RunCalibrate(const CalibrateRequest& request, const CalibrateProgress& progress) {
  app::DatasetConfig config = request.dataset_config;
  Expected<std::optional<PointTimeSelection>> times =
      SelectPointTimes(request.dataset, config, request.lo_config);
  if (!times) return times.status();
  if (*times && (*times)->convention) config.reader.point_time_convention = (*times)->convention;
  Expected<std::unique_ptr<DatasetReader>> reader = OpenDataset(request.dataset, config.reader);
  if (!reader) return reader.status();
  Expected<MeasurementStream> stream = MeasurementStream::Create(**reader, config.stream);
  if (!stream) return stream.status();
  const DatasetDescription& description = stream->description();
  const DatasetSensors sensors = FindSensors(description);
  if (sensors.lidar < 0) return MissingSensor(request.dataset, description, "a LiDAR stream");
  if (sensors.imu < 0) return MissingSensor(request.dataset, description, "an IMU stream");

  Expected<std::unique_ptr<CalibrationBranch>> branch =
      CalibrationBranch::Create(request.lo_config, *stream, sensors, /*hold_s=*/0.0, request.options);
  if (!branch) return branch.status();
  CalibrationBranch& calibration = **branch;
  const Status read = ForEachMeasurement(*stream, [&](Measurement& m) {
    if (const auto* scan = std::get_if<LidarScan>(&m.data); scan && m.stream == sensors.lidar) {
      if (Status s = calibration.AddScan(*scan); !s.ok()) return s;
      if (progress) progress(calibration.result().scans);
    } else if (const auto* sample = std::get_if<ImuSample>(&m.data); sample && m.stream == sensors.imu) {
      calibration.AddImu(*sample);
    }
    return Status();
  });
  if (!read.ok()) return read;
  calibration.Finish();
  CalibrateResult r = calibration.result();
  for (const ReadWarning& w : (*reader)->warnings())
    r.warnings.push_back(w.stream + ": " + w.what + " (" + std::to_string(w.count) + ")");
  return r;
}

Expected<std::vector<std::string>> WriteCalibrateOutputs(const fs::path& out, const CalibrateResult& r) {
  std::error_code error;
  fs::create_directories(out / "plots", error);
  if (error) return Status::Error((out / "plots").string() + ": cannot create: " + error.message());
  std::vector<std::string> written;
  if (const std::optional<SE3> T = r.TImuLidar()) {
    Calibration calibration;
    calibration.sensors.push_back({.name = r.imu_stream,
                                   .kind = SensorKind::kImu,
                                   .T_body_sensor = SE3(),
                                   .time_offset = 0,
                                   .camera_model = nullptr});
    calibration.sensors.push_back({.name = r.lidar_stream,
                                   .kind = SensorKind::kLidar,
                                   .T_body_sensor = *T,
                                   .time_offset = FromSeconds(r.LidarTimeOffset()),
                                   .camera_model = nullptr});
    const std::string header =
        std::string("Estimated by ultrafusion calibrate. time offset: ") +
        (r.time_offset_locked ? "locked"
         : r.time_offset_s    ? "not locked (latest accepted candidate)"
                              : "no estimate (the offset read with)") +
        "; rotation: " +
        (r.rotation_locked ? "locked"
         : r.UsesEstimatedRotation()
             ? "not locked, the latest accepted candidate (the given one is more than 3 "
               "sigma from it)"
         : r.R_imu_lidar ? "the given one (not locked, and the latest candidate is within 3 sigma of it)"
                         : "no estimate (the given rotation)") +
        (r.T_imu_lidar_given ? "; translation: the given one."
                             : "; translation: 0, the dataset gives no extrinsic and it is not estimated.");
    if (Status s = WriteCalibrationFile(out / "calibration_estimated.yaml", calibration, header); !s.ok())
      return s;
    written.push_back("calibration_estimated.yaml");
  }
  if (Status s = WriteTextFileAtomically(out / "calibration_solves.csv", SolvesCsv(r)); !s.ok()) return s;
  written.push_back("calibration_solves.csv");
  for (const auto& [worker, name] :
       {std::pair{CalibrationWorker::kTimeOffset, "plots/calibration_time_offset.png"},
        std::pair{CalibrationWorker::kRotation, "plots/calibration_rotation.png"}}) {
    Expected<bool> plotted = WriteWorkerPlot(out / name, r, worker);
    if (!plotted) return plotted.status();
    if (*plotted) written.push_back(name);
  }
  return written;
}

}  // namespace uf::pipeline
