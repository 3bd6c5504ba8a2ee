#include "odometry/sim/sequence/sequence_generator.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "odometry/io/atomic_file.h"
#include "odometry/io/folders/ultrafusion_dataset_writer.h"
#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sequence_measurements.h"
#include "odometry/sim/sequence/sequence_streams.h"
#include "odometry/sim/sequence/sim_trajectory.h"

namespace uf::sim {
namespace fs = std::filesystem;
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

Trajectory GroundTruth(const SimulationTrajectory& motion, double rate_hz) {
  Trajectory truth;
  const double step_ns = 1e9 / rate_hz;
  for (std::int64_t k = 0;; ++k) {
    const Stamp t = motion.begin + std::llround(static_cast<double>(k) * step_ns);
    if (t > motion.end) break;
    truth.stamps.push_back(t);
    truth.poses.push_back(motion.spline.Evaluate(t).T_world_body);
  }
  return truth;
}

Status WriteBiasTruth(const fs::path& path, const SimulatedImu& imu) {
  AtomicFileWriter file(path.string());
  if (Status s = file.status(); !s.ok()) return s;
  file.stream() << "# stamp_ns,bax,bay,baz,bgx,bgy,bgz  true IMU biases (m/s^2, rad/s, imu frame)\n";
  file.stream().precision(17);
  for (std::size_t k = 0; k < imu.samples.size(); ++k) {
    const ImuBiases& b = imu.biases[k];
    file.stream() << imu.samples[k].stamp << ',' << b.accel.x() << ',' << b.accel.y() << ',' << b.accel.z()
                  << ',' << b.gyro.x() << ',' << b.gyro.y() << ',' << b.gyro.z() << '\n';
  }
  return file.Commit();
}

// The largest |angular velocity| of the spline on a 5 ms grid.
double PeakBodyRate(const SimulationTrajectory& motion) {
  constexpr Stamp kStep = 5'000'000;
  double peak = 0.0;
  for (Stamp t = motion.begin; t <= motion.end; t += kStep)
    peak = std::max(peak, motion.spline.Evaluate(t).angular_velocity_body.norm());
  return peak;
}

double PathLength(const Trajectory& poses) {
  double length = 0.0;
  for (std::size_t i = 1; i < poses.size(); ++i)
    length += (poses.poses[i].translation() - poses.poses[i - 1].translation()).norm();
  return length;
}

// Removes what this run placed in DIR when a later step fails.
class PlacedFiles {
 public:
  explicit PlacedFiles(fs::path folder) : folder_(std::move(folder)) {}
  ~PlacedFiles() {
    if (keep_) return;
    std::error_code ignored;
    for (const std::string& name : names_) fs::remove(folder_ / name, ignored);
  }
  void Add(std::string name) { names_.push_back(std::move(name)); }
  void Keep() { keep_ = true; }
  const std::vector<std::string>& names() const { return names_; }

 private:
  fs::path folder_;
  std::vector<std::string> names_;
  bool keep_ = false;
};

}  // namespace

Expected<SimulationSummary> GenerateSequence(const SimulationConfig& config, const fs::path& out,
                                             const std::vector<ExtraFile>& extra_files,
                                             const ProgressCallback& progress) {
  if (Status s = ValidateSimulationConfig(config); !s.ok()) return s;
  std::error_code error;
  if (fs::exists(out, error) && !fs::is_empty(out, error))
    return Status::Error(out.string() + ": not empty; sim writes into a new or empty folder");
  const auto report = [&](const char* stage, std::int64_t done, std::int64_t total) {
    if (progress) progress({stage, done, total});
  };
  SimulationSummary summary;
  summary.scene = config.scene;

  // 1. The motion and the world laid out along it.
  const auto scene_start = std::chrono::steady_clock::now();
  report("trajectory", 0, 1);
  auto motion = MakeSimulationTrajectory(config);
  if (!motion) return motion.status();
  report("scene", 0, 1);
  SceneOptions scene_options{config.scene, config.seed, motion->scene_path, config.body_height_m,
                             config.origin};
  auto scene = BuildScene(scene_options);
  if (!scene) return scene.status();
  auto caster = RayCaster::Create(*scene);
  if (!caster) return caster.status();
  summary.seconds_scene = Seconds(scene_start);
  summary.duration_s = ToSeconds(motion->end - motion->begin);
  summary.path_length_m = PathLength(motion->poses);
  summary.scene_triangles = scene->mesh.triangle_count();
  summary.peak_body_rate_rad_s = PeakBodyRate(*motion);
  summary.fit_position_error_m = motion->fit_position_error_m;
  summary.fit_rotation_error_rad = motion->fit_rotation_error_rad;

  // 2. The sensors, and the order in which their measurements are stamped.
  const auto sensors_start = std::chrono::steady_clock::now();
  const std::vector<SequenceStream> streams = SequenceStreams(config);
  auto simulators = MakeSimulators(config, *motion, *caster);
  if (!simulators) return simulators.status();
  const std::vector<Event> events = Schedule(streams, *simulators, *motion);

  // 3. Generate in stamp order, writing the dataset (and the bag) as measurements come.
  fs::create_directories(out, error);
  if (error) return Status::Error(out.string() + ": cannot create the folder: " + error.message());
  auto writer = UltrafusionDatasetWriter::Create(out, DatasetStreams(config, streams));
  if (!writer) return writer.status();
  std::optional<RosBagWriter> bag;
  if (config.write_bag) {
    std::vector<BagTopic> topics;
    for (const SequenceStream& stream : streams) topics.push_back(stream.topic);
    auto created = RosBagWriter::Create(out / "sim.bag", topics);
    if (!created) return created.status();
    bag.emplace(std::move(*created));
  }
  std::vector<std::int64_t> counts(streams.size(), 0);
  std::int64_t heavy_total = 0, heavy_done = 0;  // sweeps and frames: what takes the time
  for (const Event& e : events)
    heavy_total +=
        streams[e.stream].kind == SensorKind::kLidar || streams[e.stream].kind == SensorKind::kCamera;
  std::optional<SE3> previous_scan_pose;  // T_world_lidar at the middle of the last written sweep
  for (const Event& event : events) {
    const SequenceStream& stream = streams[event.stream];
    if (stream.kind == SensorKind::kLidar) {
      const LidarSimulator& lidar = *simulators->lidar;
      const SE3 pose = motion->spline.Pose(event.true_time + lidar.period() / 2) * lidar.T_body_lidar();
      if (previous_scan_pose) {
        const SE3 step = previous_scan_pose->inverse() * pose;
        summary.max_scan_rotation_rad = std::max(summary.max_scan_rotation_rad, step.so3().Log().norm());
        summary.max_scan_translation_m = std::max(summary.max_scan_translation_m, step.translation().norm());
      }
      previous_scan_pose = pose;
    }
    auto data = Produce(event, stream, *simulators);
    if (!data) return data.status();
    if (const auto* scan = std::get_if<LidarScan>(&*data))
      summary.lidar_points += static_cast<std::int64_t>(scan->points.size());
    if (bag)
      if (Status s = bag->Write(event.stream, *data); !s.ok()) return s;
    if (Status s = writer->Write(Measurement{event.stream, std::move(*data)}); !s.ok()) return s;
    ++counts[event.stream];
    if (stream.kind == SensorKind::kLidar || stream.kind == SensorKind::kCamera)
      report("sensors", ++heavy_done, heavy_total);
  }
  if (Status s = writer->WriteGroundTruth(GroundTruth(*motion, config.ground_truth_rate_hz), config.origin);
      !s.ok())
    return s;
  summary.seconds_sensors = Seconds(sensors_start);

  // 4. Calibrations, truth and extra files, then the dataset description last.
  PlacedFiles placed(out);
  if (bag) {
    if (Status s = bag->Finish(); !s.ok()) return s;
    placed.Add("sim.bag");
  }
  const std::string header_true =
      "True calibration of this simulated sequence. time_offset_s is added to a sensor's stamps to put them\n"
      "on the IMU (body) clock; T_body_sensor maps sensor-frame points into the body (IMU) frame.";
  const std::string header_given =
      "Calibration as a user would be given it: the extrinsics carry the injected errors and the time\n"
      "offsets are unknown (0). The truth is in calibration_true.yaml.";
  if (Status s = WriteCalibrationFile(out / "calibration_true.yaml",
                                      SequenceCalibration(config, streams, true), header_true);
      !s.ok())
    return s;
  placed.Add("calibration_true.yaml");
  if (Status s = WriteCalibrationFile(out / "calibration.yaml", SequenceCalibration(config, streams, false),
                                      header_given);
      !s.ok())
    return s;
  placed.Add("calibration.yaml");
  if (simulators->imu) {
    if (Status s = WriteBiasTruth(out / "truth_imu_bias.csv", *simulators->imu); !s.ok()) return s;
    placed.Add("truth_imu_bias.csv");
  }
  for (const ExtraFile& extra : extra_files) {
    AtomicFileWriter file((out / extra.name).string());
    file.stream() << extra.text;
    if (Status s = file.Commit(); !s.ok()) return s;
    placed.Add(extra.name);
  }
  if (Status s = writer->Finish(); !s.ok()) return s;
  placed.Keep();

  for (std::size_t i = 0; i < streams.size(); ++i)
    summary.streams.push_back({streams[i].name, counts[i], streams[i].rate_hz});
  summary.files = placed.names();
  return summary;
}

}  // namespace uf::sim
