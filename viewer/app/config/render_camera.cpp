#include "viewer/app/config/render_camera.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <vector>

namespace uf::app {
namespace {

std::string Where(const std::string& path, const std::string& key, const YAML::Node& node) {
  std::string where = path + ": " + key;
  if (node.IsDefined() && node.Mark().line >= 0)
    where += " (line " + std::to_string(node.Mark().line + 1) + ")";
  return where;
}

Expected<double> Number(const std::string& path, const YAML::Node& root, const std::string& key) {
  const YAML::Node node = root[key];
  if (!node) return Status::Error(path + ": missing key '" + key + "'");
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value))
    return Status::Error(Where(path, key, node) + ": expected a finite number, got '" +
                         (node.IsScalar() ? node.Scalar() : std::string("<not a number>")) + "'");
  return value;
}

Expected<int> Size(const std::string& path, const YAML::Node& root, const std::string& key) {
  Expected<double> value = Number(path, root, key);
  if (!value) return value.status();
  if (*value < 1 || *value > 16384 || std::floor(*value) != *value)
    return Status::Error(Where(path, key, root[key]) +
                         ": expected a whole number of pixels in [1, 16384], got " + root[key].Scalar());
  return static_cast<int>(*value);
}

Status ParseDistortion(const std::string& path, const YAML::Node& node, PinholeRadtanIntrinsics& k) {
  if (!node.IsSequence() || (node.size() != 4 && node.size() != 5))
    return Status::Error(Where(path, "distortion", node) +
                         ": expected [k1, k2, p1, p2] or [k1, k2, p1, p2, k3]");
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    double value = 0;
    if (!node[i].IsScalar() || !YAML::convert<double>::decode(node[i], value) || !std::isfinite(value))
      return Status::Error(Where(path, "distortion", node) + ": entry " + std::to_string(i) +
                           " is not a finite number");
    values.push_back(value);
  }
  k.k1 = values[0];
  k.k2 = values[1];
  k.p1 = values[2];
  k.p2 = values[3];
  if (values.size() == 5) k.k3 = values[4];
  return Status();
}

Expected<RenderCamera> ParseRenderCamera(const std::string& path, const YAML::Node& root) {
  if (!root.IsMap())
    return Status::Error(path + ": expected a map with model, width, height, fx, fy, cx, cy");
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    static const std::vector<std::string> kKnown = {"model", "width", "height", "fx",
                                                    "fy",    "cx",    "cy",     "distortion"};
    if (std::find(kKnown.begin(), kKnown.end(), key) == kKnown.end())
      return Status::Error(Where(path, key, kv.first) +
                           ": unknown key (expected model, width, height, fx, fy, cx, cy, distortion)");
  }
  const YAML::Node model = root["model"];
  if (!model) return Status::Error(path + ": missing key 'model' (model: pinhole)");
  if (!model.IsScalar() || model.Scalar() != "pinhole")
    return Status::Error(Where(path, "model", model) + ": only 'pinhole' is supported, got '" +
                         (model.IsScalar() ? model.Scalar() : std::string("<not a scalar>")) + "'");
  RenderCamera camera;
  Expected<int> width = Size(path, root, "width"), height = Size(path, root, "height");
  if (!width) return width.status();
  if (!height) return height.status();
  camera.width = *width;
  camera.height = *height;
  PinholeRadtanIntrinsics& k = camera.intrinsics;
  for (auto [key, target] : {std::pair{"fx", &k.fx}, {"fy", &k.fy}, {"cx", &k.cx}, {"cy", &k.cy}}) {
    Expected<double> value = Number(path, root, key);
    if (!value) return value.status();
    *target = *value;
  }
  if (root["distortion"])
    if (Status s = ParseDistortion(path, root["distortion"], k); !s.ok()) return s;
  camera.distorted = k.k1 != 0 || k.k2 != 0 || k.p1 != 0 || k.p2 != 0 || k.k3 != 0;
  camera.model = std::make_shared<PinholeRadtan>(camera.width, camera.height, k);
  if (Status s = camera.model->Validate(); !s.ok()) return Status::Error(path + ": " + s.message());
  return camera;
}

}  // namespace

Expected<RenderCamera> LoadRenderCamera(const std::string& path) {
  try {
    return ParseRenderCamera(path, YAML::LoadFile(path));
  } catch (const YAML::BadFile&) {
    return Status::Error(path + ": cannot open the camera file");
  } catch (const YAML::Exception& e) {
    return Status::Error(path + ": " + e.what());
  }
}

RenderCamera ResizeRenderCamera(const RenderCamera& camera, int width, int height) {
  RenderCamera resized = camera;
  const double sx = static_cast<double>(width) / camera.width,
               sy = static_cast<double>(height) / camera.height;
  PinholeRadtanIntrinsics& k = resized.intrinsics;
  k.fx *= sx;
  k.fy *= sy;
  k.cx = (k.cx + 0.5) * sx - 0.5;
  k.cy = (k.cy + 0.5) * sy - 0.5;
  resized.width = width;
  resized.height = height;
  resized.model = std::make_shared<PinholeRadtan>(width, height, k);
  return resized;
}

}  // namespace uf::app
