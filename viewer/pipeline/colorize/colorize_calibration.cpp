#include "viewer/pipeline/colorize/colorize_calibration.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "odometry/io/calibration_file.h"
#include "odometry/io/dataset_reader.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string LowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// A JSON value for an error message, shortened.
std::string Shown(const json& value) {
  std::string text = value.dump();
  return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

Expected<json> ReadJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path + ": cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    return Status::Error(path + ": not valid JSON: " + e.what());
  }
}

// The first top-level entry whose `param` object holds `key`; `name` receives the entry's key. Without
// one, the error names the key missing from the first entry that has a `param` object.
Expected<const json*> FindEntry(const json& root, const std::string& file, const std::string& key,
                                std::string& name) {
  const json* first_param = nullptr;
  if (root.is_object())
    for (const auto& [entry, value] : root.items())
      if (value.is_object() && value.contains("param") && value["param"].is_object()) {
        if (value["param"].contains(key)) {
          name = entry;
          return &value["param"];
        }
        if (!first_param) {
          first_param = &value["param"];
          name = entry;
        }
      }
  if (first_param) return Status::Error(file + ": " + name + ".param: missing key '" + key + "'");
  return Status::Error(file + ": no top-level entry with param." + key +
                       " (expected {\"<name>\": {\"param\": {\"" + key + "\": ...}}})");
}

Expected<double> Number(const json& parent, const std::string& key, const std::string& where) {
  if (!parent.contains(key)) return Status::Error(where + ": missing key '" + key + "'");
  const json& value = parent[key];
  if (!value.is_number() || !std::isfinite(value.get<double>()))
    return Status::Error(where + "." + key + ": expected a finite number, got " + Shown(value));
  return value.get<double>();
}

// The numbers of `parent[key].data` (OpenCV's matrix layout: nested rows, or one flat row), row-major.
Expected<std::vector<double>> MatrixData(const json& parent, const std::string& key,
                                         const std::string& where) {
  if (!parent.contains(key)) return Status::Error(where + ": missing key '" + key + "'");
  const std::string data_where = where + "." + key + ".data";
  if (!parent[key].is_object() || !parent[key].contains("data"))
    return Status::Error(data_where + ": missing");
  const json& data = parent[key]["data"];
  if (!data.is_array()) return Status::Error(data_where + ": expected an array, got " + Shown(data));
  std::vector<double> numbers;
  for (const json& row : data) {
    for (const json& value : row.is_array() ? row : json::array({row})) {
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        return Status::Error(data_where + ": expected numbers, got " + Shown(data));
      numbers.push_back(value.get<double>());
    }
  }
  return numbers;
}

// A 4x4 homogeneous transform; the rotation part is projected onto SO(3) (R = U V^T of its SVD) because the
// files round it to about six digits, which leaves |R^T R - I| near 1e-5. Beyond 1e-3 it is no rotation.
Expected<SE3> RigidTransform(const std::vector<double>& values, const std::string& where) {
  if (values.size() != 16)
    return Status::Error(where + ": expected 4x4 = 16 numbers, got " + std::to_string(values.size()));
  const Eigen::Matrix4d T = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(values.data());
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    return Status::Error(where + ": the last row must be 0 0 0 1");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (error > 1e-3 || R.determinant() <= 0)
    return Status::Error(where + ": the rotation part is not a rotation (max |R^T R - I| = " +
                         std::to_string(error) + ", det = " + std::to_string(R.determinant()) + ")");
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix4d fixed = T;
  fixed.topLeftCorner<3, 3>() = svd.matrixU() * svd.matrixV().transpose();
  return SE3::FromMatrix(fixed);
}

Expected<LoadedIntrinsics> IntrinsicsFromJson(const std::string& path) {
  auto root = ReadJsonFile(path);
  if (!root) return root.status();
  std::string name;
  auto param = FindEntry(*root, path, "cam_K", name);
  if (!param) return param.status();
  const std::string where = path + ": " + name + ".param";
  const json& p = **param;
  auto width = Number(p, "img_dist_w", where);
  if (!width) return width.status();
  auto height = Number(p, "img_dist_h", where);
  if (!height) return height.status();
  for (const auto& [key, value] : {std::pair{"img_dist_w", *width}, std::pair{"img_dist_h", *height}})
    if (value < 1 || value > 1e5 || value != std::floor(value))
      return Status::Error(where + "." + key + ": expected a whole number of pixels in [1, 100000], got " +
                           std::to_string(value));
  auto K = MatrixData(p, "cam_K", where);
  if (!K) return K.status();
  // K = [fx s cx; 0 fy cy; 0 0 1]; the camera models have no skew s.
  if (K->size() != 9 || (*K)[1] != 0 || (*K)[3] != 0 || (*K)[6] != 0 || (*K)[7] != 0 || (*K)[8] != 1)
    return Status::Error(where + ".cam_K.data: expected [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], got " +
                         Shown(p["cam_K"]["data"]));
  auto d = MatrixData(p, "cam_dist", where);
  if (!d) return d.status();
  if (d->size() != 4 && d->size() != 5)
    return Status::Error(where + ".cam_dist.data: expected 4 or 5 radial-tangential coefficients (k1 k2 p1 " +
                         "p2 [k3]), got " + std::to_string(d->size()));
  const PinholeIntrinsics pinhole{int(*width), int(*height), (*K)[0], (*K)[4], (*K)[2], (*K)[5]};
  const PinholeRadtanIntrinsics k{pinhole, (*d)[0], (*d)[1],
                                  (*d)[2], (*d)[3], d->size() == 5 ? (*d)[4] : 0.0};
  auto camera = std::make_shared<PinholeRadtan>(k);
  if (Status s = camera->Validate(); !s.ok()) return Status::Error(where + ": " + s.message());
  return LoadedIntrinsics{camera, name + " of " + path};
}

Expected<LoadedExtrinsic> ExtrinsicFromJson(const std::string& path) {
  auto root = ReadJsonFile(path);
  if (!root) return root.status();
  std::string name;
  auto param = FindEntry(*root, path, "sensor_calib", name);
  if (!param) return param.status();
  const std::string where = path + ": " + name + ".param";
  auto data = MatrixData(**param, "sensor_calib", where);
  if (!data) return data.status();
  auto T_cam_lidar = RigidTransform(*data, where + ".sensor_calib.data");
  if (!T_cam_lidar) return T_cam_lidar.status();
  return LoadedExtrinsic{*T_cam_lidar, name + " of " + path};
}

// The sensors of one of the project's YAML files, as far as colorize needs them.
struct RigSensor {
  std::string name;
  SensorKind kind = SensorKind::kImu;
  std::optional<SE3> T_body_sensor;
  std::shared_ptr<const CameraModel> camera;
};

Expected<std::vector<RigSensor>> ReadRigYaml(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return Status::Error(path + ": cannot be read");
  } catch (const YAML::Exception& e) {
    return Status::Error(path + ": not valid YAML: " + e.what());
  }
  std::vector<RigSensor> sensors;
  if (root.IsMap() && root["calibration"]) {
    auto calibration = ReadCalibrationFile(path);
    if (!calibration) return calibration.status();
    for (const SensorCalibration& s : calibration->sensors)
      sensors.push_back({s.name, s.kind, s.T_body_sensor, s.camera_model});
    return sensors;
  }
  if (root.IsMap() && root["format"] && root["streams"]) {
    if (fs::path(path).filename() != "dataset.yaml")
      return Status::Error(path +
                           ": a dataset description is read with its folder and must be named "
                           "dataset.yaml");
    DatasetOptions options;
    options.format = DatasetFormat::kUltrafusion;
    auto reader = OpenDataset(fs::path(path).parent_path(), options);
    if (!reader) return reader.status();
    for (const StreamInfo& s : (*reader)->description().streams)
      sensors.push_back({s.name, s.kind, s.T_body_sensor, s.camera_model});
    return sensors;
  }
  return Status::Error(path +
                       ": neither a calibration file ('calibration:' section) nor a dataset.yaml "
                       "('format:' and 'streams:')");
}

const RigSensor* FirstOfKind(const std::vector<RigSensor>& sensors, SensorKind kind) {
  for (const RigSensor& s : sensors)
    if (s.kind == kind) return &s;
  return nullptr;
}

Expected<LoadedIntrinsics> IntrinsicsFromYaml(const std::string& path) {
  auto sensors = ReadRigYaml(path);
  if (!sensors) return sensors.status();
  const RigSensor* camera = FirstOfKind(*sensors, SensorKind::kCamera);
  if (!camera) return Status::Error(path + ": no camera sensor");
  if (!camera->camera) return Status::Error(path + ": camera '" + camera->name + "' has no intrinsics");
  return LoadedIntrinsics{camera->camera, "camera '" + camera->name + "' of " + path};
}

Expected<LoadedExtrinsic> ExtrinsicFromYaml(const std::string& path) {
  auto sensors = ReadRigYaml(path);
  if (!sensors) return sensors.status();
  const RigSensor* camera = FirstOfKind(*sensors, SensorKind::kCamera);
  const RigSensor* lidar = FirstOfKind(*sensors, SensorKind::kLidar);
  if (!camera) return Status::Error(path + ": no camera sensor");
  if (!lidar) return Status::Error(path + ": no lidar sensor");
  for (const RigSensor* s : {camera, lidar})
    if (!s->T_body_sensor) return Status::Error(path + ": sensor '" + s->name + "' has no T_body_sensor");
  // p_cam = T_body_cam^-1 * p_body = T_body_cam^-1 * T_body_lidar * p_lidar.
  const SE3 T_cam_lidar = camera->T_body_sensor->inverse() * *lidar->T_body_sensor;
  return LoadedExtrinsic{T_cam_lidar,
                         "T_body_" + camera->name + "^-1 * T_body_" + lidar->name + " of " + path};
}

}  // namespace

bool IsCalibrationExtension(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".json" || extension == ".yaml" || extension == ".yml";
}

Expected<LoadedIntrinsics> LoadIntrinsics(const std::string& path) {
  if (LowerExtension(path) == ".json") return IntrinsicsFromJson(path);
  return IntrinsicsFromYaml(path);
}

Expected<LoadedExtrinsic> LoadExtrinsic(const std::string& path) {
  if (LowerExtension(path) == ".json") return ExtrinsicFromJson(path);
  return ExtrinsicFromYaml(path);
}

Expected<std::shared_ptr<const CameraModel>> FitCameraToImage(const CameraModel& camera, int width,
                                                              int height, Eigen::Vector2d* shift) {
  const Eigen::Vector2d offset(0.5 * (width - camera.width()), 0.5 * (height - camera.height()));
  if (shift) *shift = offset;
  std::shared_ptr<const CameraModel> fitted;
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&camera)) {
    PinholeRadtanIntrinsics k = radtan->intrinsics();
    k.pinhole.width = width, k.pinhole.height = height;
    k.pinhole.cx += offset.x();
    k.pinhole.cy += offset.y();
    fitted = std::make_shared<PinholeRadtan>(k);
  } else if (const auto* fisheye = dynamic_cast<const Equidistant*>(&camera)) {
    EquidistantIntrinsics k = fisheye->intrinsics();
    k.pinhole.width = width, k.pinhole.height = height;
    k.pinhole.cx += offset.x();
    k.pinhole.cy += offset.y();
    fitted = std::make_shared<Equidistant>(k);
  } else {
    return Status::Error("the camera model cannot be fitted to a " + std::to_string(width) + "x" +
                         std::to_string(height) + " image");
  }
  if (Status s = fitted->Validate(); !s.ok())
    return Status::Error("the " + std::to_string(width) + "x" + std::to_string(height) +
                         " image taken as a centred crop of the calibrated " +
                         std::to_string(camera.width()) + "x" + std::to_string(camera.height()) +
                         " one: " + s.message());
  return fitted;
}

}  // namespace uf::pipeline
