#include "viewer/pipeline/run/run_record.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "odometry/io/atomic_file.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json MatrixJson(const SE3& T) {
  const Eigen::Matrix4d m = T.matrix();
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

Expected<SE3> MatrixFromJson(const json& rows, const std::string& where) {
  Eigen::Matrix4d m;
  bool valid = rows.is_array() && rows.size() == 4;
  for (int r = 0; valid && r < 4; ++r) {
    const json& row = rows[static_cast<std::size_t>(r)];
    valid = row.is_array() && row.size() == 4;
    for (int c = 0; valid && c < 4; ++c) {
      valid = row[static_cast<std::size_t>(c)].is_number();
      if (valid) m(r, c) = row[static_cast<std::size_t>(c)].get<double>();
    }
  }
  if (!valid || !m.allFinite()) return Status::Error(where + ": expected a 4x4 matrix of finite numbers");
  return SE3::FromMatrix(m);
}

// The string field `key`, parsed by `parse`; errors name the field and its value.
template <typename Parse>
auto Word(const json& root, const char* key, const std::string& path, Parse parse, const char* expected)
    -> Expected<typename decltype(parse(std::string_view()))::value_type> {
  if (!root.contains(key) || !root[key].is_string())
    return Status::Error(path + ": '" + key + "' missing or not a string");
  const std::string text = root[key].get<std::string>();
  auto value = parse(text);
  if (!value) return Status::Error(path + ": " + key + " '" + text + "' (expected " + expected + ")");
  return *value;
}

}  // namespace

Status WriteRunRecord(const fs::path& folder, const RunRecord& record) {
  const RunFrames& f = record.frames;
  const json frames = {{"T_imu_lidar", f.T_imu_lidar ? MatrixJson(*f.T_imu_lidar) : json(nullptr)},
                       {"T_estimator_body", MatrixJson(f.T_estimator_body)},
                       {"T_output_body", MatrixJson(f.T_output_body)},
                       {"T_map_world", MatrixJson(f.T_map_world)}};
  const json root = {{"dataset", record.dataset},
                     {"mode", Name(f.mode)},
                     {"output_frame", Name(f.trajectory_frame)},
                     {"map_from", Name(f.map_from)},
                     {"frames", frames}};
  AtomicFileWriter writer((folder / kRunJsonFile).string());
  if (Status s = writer.status(); !s.ok()) return s;
  writer.stream() << root.dump(2) << "\n";
  return writer.Commit();
}

Expected<RunRecord> ReadRunRecord(const fs::path& folder) {
  const fs::path file = folder / kRunJsonFile;
  const std::string path = file.string();
  const std::string rerun = " (re-run `ultrafusion run` on the dataset: runs made before it was written " +
                            std::string("have none)");
  std::error_code error;
  if (!fs::exists(file, error))
    return Status::Error(path + ": missing; it names the dataset the run read" + rerun);
  std::ifstream in(file);
  json root;
  try {
    in >> root;
  } catch (const json::exception& e) {
    return Status::Error(path + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) return Status::Error(path + ": not a JSON object");
  RunRecord record;
  if (!root.contains("dataset") || !root["dataset"].is_string())
    return Status::Error(path + ": 'dataset' missing or not a string");
  record.dataset = root["dataset"].get<std::string>();
  RunFrames& f = record.frames;
  auto mode = Word(root, "mode", path, ParseOdometryMode, "lo or lio");
  if (!mode) return mode.status();
  auto frame = Word(root, "output_frame", path, ParseTrajectoryFrame, "lidar or imu");
  if (!frame) return frame.status();
  auto map_from = Word(root, "map_from", path, ParseMapSource, "odometry or trajectory");
  if (!map_from) return map_from.status();
  f.mode = *mode, f.trajectory_frame = *frame, f.map_from = *map_from;

  if (!root.contains("frames") || !root["frames"].is_object())
    return Status::Error(path + ": 'frames' missing; it holds the run's transforms" + rerun);
  const json& frames = root["frames"];
  for (auto [key, T] : {std::pair<const char*, SE3*>{"T_estimator_body", &f.T_estimator_body},
                        {"T_output_body", &f.T_output_body},
                        {"T_map_world", &f.T_map_world}}) {
    Expected<SE3> read =
        MatrixFromJson(frames.contains(key) ? frames[key] : json(), path + ": frames." + key);
    if (!read) return read.status();
    *T = *read;
  }
  if (frames.contains("T_imu_lidar") && !frames["T_imu_lidar"].is_null()) {
    Expected<SE3> read = MatrixFromJson(frames["T_imu_lidar"], path + ": frames.T_imu_lidar");
    if (!read) return read.status();
    f.T_imu_lidar = *read;
  }
  if (!f.T_imu_lidar && (f.mode == OdometryMode::kLio || f.trajectory_frame != EstimatorFrame(f.mode)))
    return Status::Error(path + ": frames.T_imu_lidar is null, which mode " + std::string(Name(f.mode)) +
                         " with output_frame " + std::string(Name(f.trajectory_frame)) + " needs");
  return record;
}

}  // namespace uf::pipeline
