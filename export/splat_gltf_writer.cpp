// WriteSplatGlb: see splat_gltf.h for the conventions of KHR_gaussian_splatting and the change of axes.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "export/glb_file.h"
#include "export/sh_rotation.h"
#include "export/splat_gltf.h"
#include "export/splat_gltf_frames.h"

namespace uf::exporting {
namespace {

using tinygltf::Value;

// Float accessors on one binary buffer, one tightly packed view each (every offset a multiple of 4).
class FloatAccessors {
 public:
  explicit FloatAccessors(tinygltf::Model& model) : model_(model) { model_.buffers.resize(1); }

  int Add(int type, std::size_t count) {
    const std::size_t components = tinygltf::GetNumComponentsInType(type);
    std::vector<unsigned char>& data = model_.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = 4 * components * count;
    view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
    data.resize(data.size() + view.byteLength);
    model_.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model_.bufferViews.size() - 1);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.type = type;
    accessor.count = count;
    model_.accessors.push_back(accessor);
    components_.push_back(components);
    return static_cast<int>(model_.accessors.size() - 1);
  }
  // Element i of `accessor` (its components in order).
  void Put(int accessor, std::size_t i, std::initializer_list<float> values) {
    const tinygltf::BufferView& view = model_.bufferViews[model_.accessors[accessor].bufferView];
    float* out =
        reinterpret_cast<float*>(model_.buffers[0].data.data() + view.byteOffset) + components_[accessor] * i;
    for (float v : values) *out++ = v;
  }

 private:
  tinygltf::Model& model_;
  std::vector<std::size_t> components_;
};

double Sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// sRGB-encoded [0, 1] -> linear (IEC 61966-2-1), for the COLOR_0 fallback.
double SrgbDecode(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }

Value ExtensionObject() {
  Value::Object ext;
  ext["kernel"] = Value(std::string("ellipse"));
  ext["colorSpace"] = Value(std::string("srgb_rec709_display"));
  ext["projection"] = Value(std::string("perspective"));
  ext["sortingMethod"] = Value(std::string("cameraDistance"));
  return Value(ext);
}

}  // namespace

Status WriteSplatGlb(const splat::GaussianModel& model, const std::string& path) {
  if (Status valid = model.Validate(path + " (model to write)"); !valid.ok()) return valid;
  if (model.size() == 0) return Status::Error(path + ": no Gaussians to write (glTF accessors need >= 1)");
  const std::size_t n = model.size();
  const int coefficients = splat::ShCoefficientsPerChannel(model.sh_degree);
  // glb chunk lengths are uint32: keep the binary chunk (plus room for the JSON) under 4 GiB.
  const std::size_t bytes = n * 4 * (3 + 4 + 3 + 1 + 3 * coefficients + 4);
  if (bytes > 0xF0000000u)
    return Status::Error(path + ": " + std::to_string(n) + " Gaussians need " + std::to_string(bytes) +
                         " bytes, more than a .glb can hold (4 GiB)");

  tinygltf::Model gltf;
  gltf.asset.version = "2.0";
  gltf.asset.generator = "ultrafusion";
  gltf.extensionsUsed.push_back(kGaussianSplattingExtension);
  FloatAccessors accessors(gltf);
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_POINTS;
  const int position = accessors.Add(TINYGLTF_TYPE_VEC3, n);
  const int rotation = accessors.Add(TINYGLTF_TYPE_VEC4, n);
  const int scale = accessors.Add(TINYGLTF_TYPE_VEC3, n);
  const int opacity = accessors.Add(TINYGLTF_TYPE_SCALAR, n);
  std::vector<int> sh_accessors(coefficients);
  for (int k = 0; k < coefficients; ++k) sh_accessors[k] = accessors.Add(TINYGLTF_TYPE_VEC3, n);
  const int color = accessors.Add(TINYGLTF_TYPE_VEC4, n);
  primitive.attributes["POSITION"] = position;
  primitive.attributes[gltf_splat::kRotation] = rotation;
  primitive.attributes[gltf_splat::kScale] = scale;
  primitive.attributes[gltf_splat::kOpacity] = opacity;
  for (int l = 0; l <= model.sh_degree; ++l)
    for (int m = 0; m <= 2 * l; ++m)
      primitive.attributes[gltf_splat::ShAttribute(l, m)] = sh_accessors[l * l + m];
  primitive.attributes["COLOR_0"] = color;
  primitive.extensions[kGaussianSplattingExtension] = ExtensionObject();

  // To glTF's y-up frame: p' = R p, q' = q_R q, SH rotated by R (see splat_gltf.h).
  const Eigen::Matrix3d R = gltf_splat::GltfFromOurs();
  const Eigen::Quaterniond q_R(R);
  const ShRotation sh_rotation(R);
  std::vector<float> sh(model.ShStride());
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = model.positions[i];
    const Eigen::Vector3f p_gltf(p.x(), p.z(), -p.y());  // exact
    lo = lo.cwiseMin(p_gltf);
    hi = hi.cwiseMax(p_gltf);
    accessors.Put(position, i, {p_gltf.x(), p_gltf.y(), p_gltf.z()});
    const Eigen::Quaterniond q = q_R * model.rotations[i].cast<double>().normalized();
    accessors.Put(rotation, i, {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    const Eigen::Vector3d s = model.log_scales[i].cast<double>().array().exp();
    accessors.Put(scale, i, {float(s.x()), float(s.y()), float(s.z())});
    const double alpha = Sigmoid(model.opacity_logits[i]);
    accessors.Put(opacity, i, {float(alpha)});
    std::memcpy(sh.data(), model.sh.data() + i * sh.size(), sh.size() * sizeof(float));
    sh_rotation.Apply(sh.data(), model.sh_degree);
    for (int k = 0; k < coefficients; ++k)
      accessors.Put(sh_accessors[k], i, {sh[3 * k], sh[3 * k + 1], sh[3 * k + 2]});
    // COLOR_0 fallback: linear diffuse colour, alpha = opacity.
    float rgb[3];
    for (int c = 0; c < 3; ++c)
      rgb[c] = float(SrgbDecode(std::clamp(double(sh[c]) * splat::kShC0 + 0.5, 0.0, 1.0)));
    accessors.Put(color, i, {rgb[0], rgb[1], rgb[2], float(alpha)});
  }
  gltf.accessors[position].minValues = {lo.x(), lo.y(), lo.z()};
  gltf.accessors[position].maxValues = {hi.x(), hi.y(), hi.z()};

  tinygltf::Mesh mesh;
  mesh.name = "splats";
  mesh.primitives.push_back(primitive);
  gltf.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = "splats";
  node.mesh = 0;
  return WriteSingleNodeGlb(gltf, std::move(node), path);
}

}  // namespace uf::exporting
