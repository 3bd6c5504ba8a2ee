#include "odometry/io/folders/camera_calibration.h"

#include "odometry/io/folders/ultrafusion_format.h"

namespace uf {
namespace {

std::string Count(std::size_t n) { return std::to_string(n) + (n == 1 ? " value" : " values"); }

}  // namespace

Expected<std::shared_ptr<const CameraModel>> ParseCameraCalibration(const YAML::Node& node,
                                                                    const std::string& where) {
  if (node["camera_model"] && node["camera_model"].as<std::string>() != "pinhole")
    return Status::Error(where + ": camera_model '" + node["camera_model"].as<std::string>() +
                         "' is not supported (pinhole)");
  for (const char* key : {"distortion_model", "intrinsics", "distortion_coefficients", "resolution"})
    if (!node[key]) return Status::Error(where + ": camera calibration without '" + key + "'");
  const std::string model = node["distortion_model"].as<std::string>();
  const auto k = node["intrinsics"].as<std::vector<double>>();
  const auto d = node["distortion_coefficients"].as<std::vector<double>>();
  const auto size = node["resolution"].as<std::vector<int>>();
  if (k.size() != 4)
    return Status::Error(where + ": intrinsics needs 4 values (fx, fy, cx, cy), found " + Count(k.size()));
  if (size.size() != 2)
    return Status::Error(where + ": resolution needs 2 values (width, height), found " + Count(size.size()));
  const PinholeIntrinsics pinhole{size[0], size[1], k[0], k[1], k[2], k[3]};
  std::shared_ptr<const CameraModel> camera;
  if (model == "radial-tangential") {
    if (d.size() != 4 && d.size() != 5)
      return Status::Error(
          where +
          ": radial-tangential distortion_coefficients needs 4 or 5 values (k1, k2, p1, p2[, k3]), found " +
          Count(d.size()));
    camera = std::make_shared<PinholeRadtan>(
        PinholeRadtanIntrinsics{pinhole, d[0], d[1], d[2], d[3], d.size() == 5 ? d[4] : 0});
  } else if (model == "equidistant") {
    if (d.size() != 4)
      return Status::Error(where + ": equidistant distortion_coefficients needs 4 values (k1..k4), found " +
                           Count(d.size()));
    camera = std::make_shared<Equidistant>(EquidistantIntrinsics{pinhole, d[0], d[1], d[2], d[3]});
  } else {
    return Status::Error(where + ": distortion_model '" + model +
                         "' is not radial-tangential or equidistant");
  }
  if (Status s = camera->Validate(); !s.ok()) return Status::Error(where + ": " + s.message());
  return camera;
}

void EmitCameraCalibration(YAML::Emitter& yaml, const CameraModel& model) {
  using ultrafusion_format::FormatNumber;
  auto sequence = [&yaml](const char* key, std::initializer_list<double> values) {
    yaml << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (double v : values) yaml << FormatNumber(v);
    yaml << YAML::EndSeq;
  };
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&model)) {
    const PinholeRadtanIntrinsics& k = radtan->intrinsics();
    yaml << YAML::Key << "distortion_model" << YAML::Value << "radial-tangential";
    sequence("intrinsics", {k.pinhole.fx, k.pinhole.fy, k.pinhole.cx, k.pinhole.cy});
    sequence("distortion_coefficients", {k.k1, k.k2, k.p1, k.p2, k.k3});
  } else if (const auto* fisheye = dynamic_cast<const Equidistant*>(&model)) {
    const EquidistantIntrinsics& k = fisheye->intrinsics();
    yaml << YAML::Key << "distortion_model" << YAML::Value << "equidistant";
    sequence("intrinsics", {k.pinhole.fx, k.pinhole.fy, k.pinhole.cx, k.pinhole.cy});
    sequence("distortion_coefficients", {k.k1, k.k2, k.k3, k.k4});
  }
  yaml << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq << model.width()
       << model.height() << YAML::EndSeq;
}

}  // namespace uf
