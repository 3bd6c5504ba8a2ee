#include "export/gltf_writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

#include "export/glb_file.h"
#include "export/output_frame.h"

namespace uf::exporting {
namespace {

using tinygltf::Value;

// z-up (ours) -> y-up (glTF): a -90 deg rotation about x, (x, y, z) -> (x, z, -y).
Eigen::Vector3d ToYUp(const Eigen::Vector3d& v) { return {v.x(), v.z(), -v.y()}; }

// sRGB byte -> linear [0, 1] (IEC 61966-2-1 decoding).
float SrgbToLinear(std::uint8_t c) {
  const double s = c / 255.0;
  return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

// Fills one shared binary buffer with tightly packed views (each a multiple of 4 bytes, so every view and
// every element stays 4-byte aligned as glTF requires for vertex attributes).
class GlbBuffer {
 public:
  GlbBuffer(tinygltf::Model& model, const std::array<std::uint8_t, 3>& uncolored, bool linear_colors)
      : model_(model), uncolored_(uncolored), linear_colors_(linear_colors) {
    for (int c = 0; c < 256; ++c) linear_[c] = SrgbToLinear(static_cast<std::uint8_t>(c));
  }
  std::size_t ColorBytes() const { return linear_colors_ ? 12 : 4; }

  // A view of `bytes` at the end of the buffer and an accessor of `count` elements on it.
  int AddAccessor(std::size_t bytes, int target, int component, int type, std::size_t count,
                  bool normalized) {
    std::vector<unsigned char>& data = model_.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = bytes;
    view.target = target;
    data.resize(data.size() + bytes);
    model_.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model_.bufferViews.size() - 1);
    accessor.componentType = component;
    accessor.type = type;
    accessor.count = count;
    accessor.normalized = normalized;
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size() - 1);
  }
  int AddVec3f(std::size_t count) {
    return AddAccessor(12 * count, TINYGLTF_TARGET_ARRAY_BUFFER, TINYGLTF_COMPONENT_TYPE_FLOAT,
                       TINYGLTF_TYPE_VEC3, count, false);
  }
  int AddColors(std::size_t count) {
    return linear_colors_
               ? AddVec3f(count)
               : AddAccessor(4 * count, TINYGLTF_TARGET_ARRAY_BUFFER, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                             TINYGLTF_TYPE_VEC4, count, true);
  }
  unsigned char* At(int accessor, std::size_t byte) {
    const tinygltf::BufferView& view = model_.bufferViews[model_.accessors[accessor].bufferView];
    return model_.buffers[0].data.data() + view.byteOffset + byte;
  }
  void PutVec3f(int accessor, std::size_t i, const Eigen::Vector3f& v) {
    std::memcpy(At(accessor, 12 * i), v.data(), 12);
  }
  void PutColor(int accessor, std::size_t i, const std::array<std::uint8_t, 3>& rgb, bool has_color) {
    const std::array<std::uint8_t, 3>& c = has_color ? rgb : uncolored_;
    if (linear_colors_) {
      PutVec3f(accessor, i, Eigen::Vector3f(linear_[c[0]], linear_[c[1]], linear_[c[2]]));
    } else {
      const std::uint8_t rgba[4] = {c[0], c[1], c[2], 255};
      std::memcpy(At(accessor, 4 * i), rgba, 4);
    }
  }
  // POSITION accessors must carry the exact min and max of their (float) values.
  void SetMinMaxVec3f(int accessor) {
    tinygltf::Accessor& a = model_.accessors[accessor];
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
    for (std::size_t i = 0; i < a.count; ++i) {
      Eigen::Vector3f v;
      std::memcpy(v.data(), At(accessor, 12 * i), 12);
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    a.minValues = {lo.x(), lo.y(), lo.z()};
    a.maxValues = {hi.x(), hi.y(), hi.z()};
  }

 private:
  tinygltf::Model& model_;
  std::array<std::uint8_t, 3> uncolored_;
  bool linear_colors_;
  std::array<float, 256> linear_{};
};

// Checks the mesh and returns the output-frame bounds of its vertices.
Expected<Eigen::AlignedBox3d> CheckMesh(const mapping::ColoredMesh& mesh, const OutputFrame& frame,
                                        const std::string& name) {
  const std::size_t n = mesh.vertices.size();
  if (mesh.colors.size() != n)
    return Status::Error(name + ": mesh has " + std::to_string(mesh.colors.size()) + " colours for " +
                         std::to_string(n) + " vertices");
  if (!mesh.normals.empty() && mesh.normals.size() != n)
    return Status::Error(name + ": mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
                         std::to_string(n) + " vertices");
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.vertices[i].allFinite())
      return Status::Error(name + ": mesh vertex " + std::to_string(i) + " is not finite");
    box.extend(frame.Apply(mesh.vertices[i]));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t index : mesh.triangles[t])
      if (index >= n)
        return Status::Error(name + ": mesh triangle " + std::to_string(t) + " has vertex index " +
                             std::to_string(index) + " >= " + std::to_string(n) + " vertices");
  return box;
}

bool UsableNormals(const mapping::ColoredMesh& mesh) {
  if (mesh.normals.empty()) return false;
  for (const Eigen::Vector3f& n : mesh.normals)
    if (!n.allFinite() || n.norm() < 1e-6f) return false;
  return true;
}

tinygltf::Primitive PointsPrimitive(const mapping::PointSource& points, std::size_t kept, std::size_t stride,
                                    const OutputFrame& frame, const Eigen::Vector3d& origin,
                                    GlbBuffer& buffer) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_POINTS;
  const int position = buffer.AddVec3f(kept), color = buffer.AddColors(kept);
  std::size_t finite_index = 0, out = 0;
  points.ForEachChunk([&](std::span<const mapping::MapPoint> chunk) {
    for (const mapping::MapPoint& p : chunk) {
      if (!p.position.allFinite() || finite_index++ % stride != 0) continue;
      buffer.PutVec3f(position, out, ToYUp(frame.Apply(p.position) - origin).cast<float>());
      buffer.PutColor(color, out, p.rgb, p.has_color);
      ++out;
    }
    return true;
  });
  assert(out == kept);
  buffer.SetMinMaxVec3f(position);
  primitive.attributes["POSITION"] = position;
  primitive.attributes["COLOR_0"] = color;
  return primitive;
}

tinygltf::Primitive MeshPrimitive(const mapping::ColoredMesh& mesh, const OutputFrame& frame,
                                  const Eigen::Vector3d& origin, GlbBuffer& buffer) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const std::size_t n = mesh.vertices.size();
  const int position = buffer.AddVec3f(n);
  for (std::size_t i = 0; i < n; ++i)
    buffer.PutVec3f(position, i, ToYUp(frame.Apply(mesh.vertices[i]) - origin).cast<float>());
  buffer.SetMinMaxVec3f(position);
  primitive.attributes["POSITION"] = position;
  // Normals are directions: in UTM they keep their ENU components (the grid convergence, < 3 deg within a
  // zone, is not applied).
  if (UsableNormals(mesh)) {
    const int normal = buffer.AddVec3f(n);
    for (std::size_t i = 0; i < n; ++i)
      buffer.PutVec3f(normal, i, ToYUp(mesh.normals[i].cast<double>().normalized()).cast<float>());
    primitive.attributes["NORMAL"] = normal;
  }
  const int color = buffer.AddColors(n);
  for (std::size_t i = 0; i < n; ++i) buffer.PutColor(color, i, mesh.colors[i], true);
  primitive.attributes["COLOR_0"] = color;
  primitive.indices = buffer.AddAccessor(12 * mesh.triangles.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                         3 * mesh.triangles.size(), false);
  std::memcpy(buffer.At(primitive.indices, 0), mesh.triangles.data(), 12 * mesh.triangles.size());
  return primitive;
}

// Unlit material for the points (base colour white times COLOR_0, shown as stored).
int AddPointsMaterial(tinygltf::Model& model) {
  tinygltf::Material points;
  points.name = "map points";
  points.pbrMetallicRoughness.metallicFactor = 0.0;
  points.extensions["KHR_materials_unlit"] = Value(Value::Object());
  model.materials.push_back(points);
  model.extensionsUsed.push_back("KHR_materials_unlit");
  return static_cast<int>(model.materials.size() - 1);
}

// Matte, lit, double-sided material for the mesh (glTF's default is fully metallic, which shows vertex
// colours almost black).
int AddMeshMaterial(tinygltf::Model& model) {
  tinygltf::Material surface;
  surface.name = "map mesh";
  surface.pbrMetallicRoughness.metallicFactor = 0.0;
  surface.pbrMetallicRoughness.roughnessFactor = 1.0;
  surface.doubleSided = true;
  model.materials.push_back(surface);
  return static_cast<int>(model.materials.size() - 1);
}

Value AssetExtras(const OutputFrame& frame, std::size_t stride, std::size_t finite, std::size_t kept) {
  Value::Object info;
  info["frame"] = Value(std::string(OutputCrsName(frame.crs())));
  info["axes"] = Value(std::string("(x, y, z)_gltf = (x, z, -y)_frame, frame z up"));
  info["point_stride"] = Value(static_cast<int>(stride));
  info["points_finite"] = Value(static_cast<double>(finite));
  info["points_written"] = Value(static_cast<double>(kept));
  if (const Georeference* g = frame.georef(); g && frame.crs() != OutputCrs::kLocal) {
    const GeodeticOrigin& o = g->origin();
    info["origin_wgs84"] =
        Value(Value::Array{Value(o.latitude_deg), Value(o.longitude_deg), Value(o.height_m)});
    if (frame.crs() == OutputCrs::kUtm) info["epsg"] = Value(g->epsg());
  }
  return Value(Value::Object{{"ultrafusion", Value(info)}});
}

}  // namespace

Status WriteGlb(const std::filesystem::path& path, const mapping::PointSource* points,
                const mapping::ColoredMesh* mesh, const GltfOptions& options, ExportStats* stats) {
  const std::string name = path.string();
  if (options.max_points == 0) return Status::Error(name + ": gltf.max_points: must be > 0, got 0");
  Expected<OutputFrame> frame = OutputFrame::Create(options.crs, options.georef, name);
  if (!frame.ok()) return frame.status();

  // Bounds of everything, in the output frame: points (first pass) and mesh vertices.
  FinitePoints finite;
  if (points) finite = ScanFinitePoints(*points);
  const bool has_mesh = mesh && !mesh->empty();
  if (finite.finite == 0 && !has_mesh)
    return Status::Error(name + ": nothing to write, no finite point (" + std::to_string(finite.nonfinite) +
                         " non-finite) and no mesh");
  Eigen::AlignedBox3d box = frame->ApplyToBox(finite.bounds);
  if (has_mesh) {
    Expected<Eigen::AlignedBox3d> mesh_box = CheckMesh(*mesh, *frame, name);
    if (!mesh_box.ok()) return mesh_box.status();
    box.extend(*mesh_box);
  }
  const Eigen::Vector3d origin = box.center().array().round();  // local origin, output frame (z up)
  const std::size_t stride =
      std::max<std::size_t>(1, (finite.finite + options.max_points - 1) / options.max_points);
  const std::size_t kept = (finite.finite + stride - 1) / stride;

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "ultrafusion";
  model.asset.extras = AssetExtras(*frame, stride, finite.finite, kept);
  model.buffers.resize(1);
  GlbBuffer buffer(model, options.uncolored_rgb, options.linear_float_colors);
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = "map";
  if (kept > 0) {
    gltf_mesh.primitives.push_back(PointsPrimitive(*points, kept, stride, *frame, origin, buffer));
    gltf_mesh.primitives.back().material = AddPointsMaterial(model);
  }
  if (has_mesh) {
    gltf_mesh.primitives.push_back(MeshPrimitive(*mesh, *frame, origin, buffer));
    gltf_mesh.primitives.back().material = AddMeshMaterial(model);
  }
  model.meshes.push_back(std::move(gltf_mesh));
  // glb chunk lengths are uint32: keep the binary chunk (plus room for the JSON) under 4 GiB.
  constexpr std::size_t kMaxBinaryBytes = 0xF0000000u;
  if (model.buffers[0].data.size() > kMaxBinaryBytes)
    return Status::Error(
        name + ": " + std::to_string(model.buffers[0].data.size()) +
        " bytes of geometry exceed what a .glb can hold (4 GiB); lower gltf.max_points or the "
        "mesh size");
  tinygltf::Node node;
  node.name = "map";
  node.mesh = 0;
  const Eigen::Vector3d translation = ToYUp(origin);
  node.translation = {translation.x(), translation.y(), translation.z()};
  std::uint64_t bytes = 0;
  if (Status s = WriteSingleNodeGlb(model, std::move(node), name, &bytes); !s.ok()) return s;
  if (stats) *stats = {kept, finite.nonfinite, stride, bytes};
  return {};
}

}  // namespace uf::exporting
