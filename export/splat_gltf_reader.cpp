// ReadSplatGltf: see splat_gltf.h for the conventions of KHR_gaussian_splatting and the change of axes.
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>

#include "export/sh_rotation.h"
#include "export/splat_gltf.h"
#include "export/splat_gltf_frames.h"

namespace uf::exporting {
namespace {

using splat::GaussianModel;

// One accessor as floats (count x components), normalized integer types mapped to [0, 1] / [-1, 1] as glTF
// defines; every offset and length is checked against the buffer before reading.
Expected<std::vector<float>> ReadAccessor(const tinygltf::Model& m, int index, int type,
                                          const std::string& what) {
  if (index < 0 || index >= static_cast<int>(m.accessors.size()))
    return Status::Error(what + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = m.accessors[index];
  if (a.type != type)
    return Status::Error(what + ": accessor " + std::to_string(index) + " has the wrong type");
  if (a.sparse.isSparse) return Status::Error(what + ": sparse accessors are not supported");
  const int components = tinygltf::GetNumComponentsInType(type);
  const int size = tinygltf::GetComponentSizeInBytes(a.componentType);
  if (size <= 0) return Status::Error(what + ": unknown component type " + std::to_string(a.componentType));
  if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m.bufferViews.size()))
    return Status::Error(what + ": accessor " + std::to_string(index) + " has no valid bufferView");
  const tinygltf::BufferView& view = m.bufferViews[a.bufferView];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(m.buffers.size()))
    return Status::Error(what + ": bufferView " + std::to_string(a.bufferView) + " has no valid buffer");
  const std::vector<unsigned char>& data = m.buffers[view.buffer].data;
  const std::size_t element = std::size_t(components) * size;
  const std::size_t stride = view.byteStride ? view.byteStride : element;
  if (stride < element || view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset ||
      a.byteOffset > view.byteLength || a.count == 0 || view.byteLength - a.byteOffset < element ||
      (a.count - 1) > (view.byteLength - a.byteOffset - element) / stride)
    return Status::Error(what + ": accessor " + std::to_string(index) + " (" + std::to_string(a.count) +
                         " elements) does not fit its bufferView / buffer");
  std::vector<float> out(a.count * components);
  const unsigned char* base = data.data() + view.byteOffset + a.byteOffset;
  for (std::size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = base + i * stride + std::size_t(c) * size;
      auto load = [p]<typename T>(T) {
        T v;
        std::memcpy(&v, p, sizeof(T));
        return v;
      };
      float& v = out[i * components + c];
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          v = load(float{});
          break;
        case TINYGLTF_COMPONENT_TYPE_BYTE:
          v = a.normalized ? std::max(load(std::int8_t{}) / 127.0f, -1.0f) : load(std::int8_t{});
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          v = load(std::uint8_t{}) / (a.normalized ? 255.0f : 1.0f);
          break;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
          v = a.normalized ? std::max(load(std::int16_t{}) / 32767.0f, -1.0f) : load(std::int16_t{});
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
          v = load(std::uint16_t{}) / (a.normalized ? 65535.0f : 1.0f);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          v = static_cast<float>(load(std::uint32_t{}));
          break;
        default:
          return Status::Error(what + ": unsupported component type " + std::to_string(a.componentType));
      }
    }
  return out;
}

Eigen::Matrix4d LocalMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return Eigen::Map<const Eigen::Matrix4d>(node.matrix.data());  // column-major
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) T.translate(Eigen::Vector3d(node.translation.data()));
  if (node.rotation.size() == 4)
    T.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])
                 .normalized());
  if (node.scale.size() == 3) T.scale(Eigen::Vector3d(node.scale.data()));
  return T.matrix();
}

// Every (mesh, global transform) the default scene instantiates (every mesh, untransformed, without scenes).
Status CollectMeshes(const tinygltf::Model& m, const std::string& path,
                     std::vector<std::pair<int, Eigen::Matrix4d>>& out) {
  const int scene = m.defaultScene >= 0 ? m.defaultScene : (m.scenes.empty() ? -1 : 0);
  if (scene >= static_cast<int>(m.scenes.size())) return Status::Error(path + ": scene index out of range");
  if (scene < 0) {
    for (std::size_t mesh = 0; mesh < m.meshes.size(); ++mesh)
      out.emplace_back(int(mesh), Eigen::Matrix4d::Identity());
    return {};
  }
  std::vector<std::pair<int, Eigen::Matrix4d>> stack;
  for (int root : m.scenes[scene].nodes) stack.emplace_back(root, Eigen::Matrix4d::Identity());
  std::size_t visits = 0;
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || index >= static_cast<int>(m.nodes.size()) || ++visits > m.nodes.size())
      return Status::Error(path + ": node " + std::to_string(index) + " is out of range or in a cycle");
    const tinygltf::Node& node = m.nodes[index];
    const Eigen::Matrix4d global = parent * LocalMatrix(node);
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(m.meshes.size()))
        return Status::Error(path + ": mesh index out of range");
      out.emplace_back(node.mesh, global);
    }
    for (int child : node.children) stack.emplace_back(child, global);
  }
  return {};
}

std::string StringProperty(const tinygltf::Value& object, const char* key, const char* fallback) {
  if (!object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  return v.IsString() ? v.Get<std::string>() : std::string("(not a string)");
}

Status CheckExtensionObject(const tinygltf::Value& ext, const std::string& where) {
  const std::string kernel = StringProperty(ext, "kernel", "ellipse");
  const std::string color = StringProperty(ext, "colorSpace", "srgb_rec709_display");
  const std::string projection = StringProperty(ext, "projection", "perspective");
  if (kernel != "ellipse")
    return Status::Error(where + ": kernel '" + kernel + "' is not supported (only 'ellipse')");
  if (color != "srgb_rec709_display")
    return Status::Error(
        where + ": colorSpace '" + color +
        "' is not supported; the splats here are display-referred sRGB ('srgb_rec709_display')");
  if (projection != "perspective")
    return Status::Error(where + ": projection '" + projection + "' is not supported");
  if (ext.Has("extensions") && ext.Get("extensions").IsObject() && !ext.Get("extensions").Keys().empty())
    return Status::Error(where + ": extension '" + ext.Get("extensions").Keys().front() +
                         "' of KHR_gaussian_splatting (e.g. compression) is not supported");
  return {};
}

// The splats of one primitive, with the global transform M (glTF frame) applied and taken to our frame.
Expected<GaussianModel> ReadPrimitive(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                                      const Eigen::Matrix4d& M, const std::string& where) {
  if (prim.mode != TINYGLTF_MODE_POINTS)
    return Status::Error(where + ": mode must be POINTS (0), got " + std::to_string(prim.mode));
  if (Status s = CheckExtensionObject(prim.extensions.at(kGaussianSplattingExtension), where); !s.ok())
    return s;
  auto attribute = [&](const std::string& name) {
    const auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
  };
  for (const std::string& name : {std::string("POSITION"), gltf_splat::kRotation, gltf_splat::kScale,
                                  gltf_splat::kOpacity, gltf_splat::ShAttribute(0, 0)})
    if (attribute(name) < 0) return Status::Error(where + ": attribute '" + name + "' is missing");
  // SH degree: the highest l with all of COEF_0..2l present; partial or skipped degrees are errors.
  int degree = 0;
  for (int l = 1; l <= splat::kMaxShDegree; ++l) {
    int present = 0;
    for (int n = 0; n <= 2 * l; ++n) present += attribute(gltf_splat::ShAttribute(l, n)) >= 0;
    if (present > 0 && (present < 2 * l + 1 || degree != l - 1))
      return Status::Error(where + ": spherical harmonics degree " + std::to_string(l) +
                           " is partially defined or "
                           "follows a missing degree (" +
                           std::to_string(present) + " of " + std::to_string(2 * l + 1) + " coefficients)");
    if (present > 0) degree = l;
  }
  GaussianModel part;
  part.sh_degree = degree;
  const int K = splat::ShCoefficientsPerChannel(degree);
  std::vector<std::vector<float>> columns;  // position, rotation, scale, opacity, SH_0 .. SH_{K-1}
  const std::pair<std::string, int> wanted[4] = {{"POSITION", TINYGLTF_TYPE_VEC3},
                                                 {gltf_splat::kRotation, TINYGLTF_TYPE_VEC4},
                                                 {gltf_splat::kScale, TINYGLTF_TYPE_VEC3},
                                                 {gltf_splat::kOpacity, TINYGLTF_TYPE_SCALAR}};
  for (const auto& [name, type] : wanted) {
    Expected<std::vector<float>> values = ReadAccessor(m, attribute(name), type, where + " " + name);
    if (!values.ok()) return values.status();
    columns.push_back(std::move(values.value()));
  }
  for (int l = 0; l <= degree; ++l)
    for (int n = 0; n <= 2 * l; ++n) {
      const std::string name = gltf_splat::ShAttribute(l, n);
      Expected<std::vector<float>> values =
          ReadAccessor(m, attribute(name), TINYGLTF_TYPE_VEC3, where + " " + name);
      if (!values.ok()) return values.status();
      columns.push_back(std::move(values.value()));
    }
  const std::size_t count = columns[0].size() / 3;
  const int per_element[4] = {3, 4, 3, 1};
  for (std::size_t c = 1; c < columns.size(); ++c)
    if (columns[c].size() != count * (c < 4 ? per_element[c] : 3))
      return Status::Error(where + ": attributes have different counts (" + std::to_string(count) +
                           " positions)");

  // Global transform M = [A t]: A = s R_node with a uniform positive scale s, then our frame from glTF's.
  const Eigen::Matrix3d A = M.topLeftCorner<3, 3>();
  const Eigen::Vector3d s = A.colwise().norm();
  const Eigen::Matrix3d R_node = A / s.mean();
  if (!M.allFinite() || s.minCoeff() <= 0 || s.maxCoeff() > s.minCoeff() * (1 + 1e-5) ||
      std::abs(R_node.determinant() - 1) > 1e-4)
    return Status::Error(where +
                         ": the node transform is not translation + rotation + uniform positive scale");
  const Eigen::Matrix3d R_ours = gltf_splat::GltfFromOurs().transpose();
  const Eigen::Matrix3d R_total = R_ours * R_node;
  const Eigen::Quaterniond q_total(R_total);
  const ShRotation sh_rotation(R_total);
  const double log_s = std::log(s.mean());
  std::vector<float> sh(part.ShStride());
  for (std::size_t i = 0; i < count; ++i) {
    const float* p = &columns[0][3 * i];
    const float* q = &columns[1][4 * i];  // x y z w
    const float* scale = &columns[2][3 * i];
    const double opacity = columns[3][i];
    if (!(opacity >= 0 && opacity <= 1))
      return Status::Error(where + ": Gaussian " + std::to_string(i) + ": opacity must be in [0, 1], got " +
                           std::to_string(opacity));
    Eigen::Vector3f log_scale;
    for (int a = 0; a < 3; ++a) {
      if (!(scale[a] > 0))
        return Status::Error(where + ": Gaussian " + std::to_string(i) + ": scale_" + std::to_string(a) +
                             " must be positive, got " + std::to_string(scale[a]));
      log_scale[a] = static_cast<float>(std::log(double(scale[a])) + log_s);
    }
    const Eigen::Vector3d position =
        R_ours * (A * Eigen::Vector3d(p[0], p[1], p[2]) + M.topRightCorner<3, 1>());
    const Eigen::Quaterniond rotation = q_total * Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    for (int k = 0; k < K; ++k)
      for (int c = 0; c < 3; ++c) sh[3 * k + c] = columns[4 + k][3 * i + c];
    sh_rotation.Apply(sh.data(), degree);
    const double clamped = std::clamp(opacity, 1e-9, 1 - 1e-9);
    part.Add(position.cast<float>(), log_scale, rotation.cast<float>(),
             static_cast<float>(std::log(clamped / (1 - clamped))), sh.data());
  }
  return part;
}

// Appends `part` to `model`, whose SH degree is at least the part's (missing coefficients are zero).
void Append(const GaussianModel& part, GaussianModel& model) {
  std::vector<float> sh(model.ShStride(), 0.0f);
  for (std::size_t i = 0; i < part.size(); ++i) {
    std::copy_n(part.sh.data() + i * part.ShStride(), part.ShStride(), sh.begin());
    model.Add(part.positions[i], part.log_scales[i], part.rotations[i], part.opacity_logits[i], sh.data());
  }
}

}  // namespace

Expected<GaussianModel> ReadSplatGltf(const std::string& path) {
  char magic[4] = {};
  std::ifstream(path, std::ios::binary).read(magic, 4);
  const bool binary = std::string(magic, 4) == "glTF";
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  const bool loaded = binary ? loader.LoadBinaryFromFile(&m, &err, &warn, path)
                             : loader.LoadASCIIFromFile(&m, &err, &warn, path);
  if (!loaded) return Status::Error(path + ": not a readable glTF file: " + err.substr(0, 400));
  for (const std::string& required : m.extensionsRequired)
    if (required != kGaussianSplattingExtension)
      return Status::Error(path + ": requires the glTF extension '" + required + "', which is not supported");
  std::vector<std::pair<int, Eigen::Matrix4d>> meshes;
  if (Status s = CollectMeshes(m, path, meshes); !s.ok()) return s;
  std::vector<GaussianModel> parts;
  int degree = 0;
  for (const auto& [mesh, M] : meshes)
    for (std::size_t p = 0; p < m.meshes[mesh].primitives.size(); ++p) {
      const tinygltf::Primitive& prim = m.meshes[mesh].primitives[p];
      if (!prim.extensions.count(kGaussianSplattingExtension)) continue;
      const std::string where = path + ": mesh " + std::to_string(mesh) + " primitive " + std::to_string(p);
      Expected<GaussianModel> part = ReadPrimitive(m, prim, M, where);
      if (!part.ok()) return part.status();
      degree = std::max(degree, part->sh_degree);
      parts.push_back(std::move(part.value()));
    }
  if (parts.empty())
    return Status::Error(path + ": no mesh primitive with the KHR_gaussian_splatting extension in the scene");
  GaussianModel model;
  model.sh_degree = degree;
  for (const GaussianModel& part : parts) Append(part, model);
  if (Status valid = model.Validate(path); !valid.ok()) return valid;
  return model;
}

}  // namespace uf::exporting
