#include "odometry/io/camera_calibration.h"

#include <algorithm>
#include <vector>

#include "odometry/io/folders/ultrafusion_format.h"

namespace uf {
namespace {

// The scalar's text, or a list or map on one line.
std::string Text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter flow;
  flow << YAML::Flow << node;
  return flow.c_str();
}

// 'text' (appended piece by piece: GCC 12 warns falsely on "literal" + std::string chains).
std::string Quoted(const std::string& text) {
  std::string quoted = "'";
  quoted += text;
  quoted += '\'';
  return quoted;
}

Status KeyError(const std::string& where, const char* key, const YAML::Node& value, const std::string& what) {
  return Status::Error(where + ": " + key + " (line " + std::to_string(value.Mark().line + 1) + "): " + what);
}

// node[key] as a list of numbers of type T with one of the given lengths.
template <typename T>
Expected<std::vector<T>> List(const YAML::Node& node, const std::string& where, const char* key,
                              std::initializer_list<std::size_t> sizes, const std::string& needs) {
  const YAML::Node list = node[key];
  std::vector<T> values;
  bool ok = list.IsSequence();
  for (std::size_t i = 0; ok && i < list.size(); ++i) {
    T value{};
    ok = YAML::convert<T>::decode(list[i], value);
    values.push_back(value);
  }
  if (!ok || std::find(sizes.begin(), sizes.end(), values.size()) == sizes.end())
    return KeyError(where, key, list, "needs " + needs + ", found " + Quoted(Text(list)));
  return values;
}

}  // namespace

Expected<std::shared_ptr<const CameraModel>> ParseCameraCalibration(const YAML::Node& node,
                                                                    const std::string& where) {
  if (!node.IsMap()) return Status::Error(where + ": expected a map of camera intrinsics");
  if (const YAML::Node camera_model = node["camera_model"]; camera_model && Text(camera_model) != "pinhole")
    return KeyError(where, "camera_model", camera_model,
                    Quoted(Text(camera_model)) + " is not supported (pinhole)");
  for (const char* key : {"distortion_model", "intrinsics", "distortion_coefficients", "resolution"})
    if (!node[key]) return Status::Error(where + ": camera calibration without '" + key + "'");
  const std::string model = Text(node["distortion_model"]);
  const bool radtan = model == "radial-tangential";
  if (!radtan && model != "equidistant")
    return KeyError(where, "distortion_model", node["distortion_model"],
                    Quoted(model) + " is not radial-tangential or equidistant");
  const auto k = List<double>(node, where, "intrinsics", {4}, "4 numbers (fx, fy, cx, cy)");
  if (!k) return k.status();
  const auto size = List<int>(node, where, "resolution", {2}, "2 whole numbers (width, height)");
  if (!size) return size.status();
  const auto d = radtan ? List<double>(node, where, "distortion_coefficients", {4, 5},
                                       "4 or 5 numbers for radial-tangential (k1, k2, p1, p2[, k3])")
                        : List<double>(node, where, "distortion_coefficients", {4},
                                       "4 numbers for equidistant (k1, k2, k3, k4)");
  if (!d) return d.status();
  const PinholeIntrinsics pinhole{(*size)[0], (*size)[1], (*k)[0], (*k)[1], (*k)[2], (*k)[3]};
  std::shared_ptr<const CameraModel> camera;
  if (radtan) {
    camera = std::make_shared<PinholeRadtan>(
        PinholeRadtanIntrinsics{pinhole, (*d)[0], (*d)[1], (*d)[2], (*d)[3], d->size() == 5 ? (*d)[4] : 0});
  } else {
    camera =
        std::make_shared<Equidistant>(EquidistantIntrinsics{pinhole, (*d)[0], (*d)[1], (*d)[2], (*d)[3]});
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
