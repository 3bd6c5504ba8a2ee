// glb files read back with tinygltf's loader; positions + node translation must reproduce the input after
// undoing the documented y-up conversion, (x, y, z)_gltf = (x, z, -y)_map.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "export/gltf_writer.h"
#include "export_test_util.h"
#include "gltf_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

using test::LoadGlb;

template <typename T>
std::vector<T> AccessorData(const tinygltf::Model& m, int accessor_index, int components) {
  const tinygltf::Accessor& a = m.accessors.at(accessor_index);
  const tinygltf::BufferView& v = m.bufferViews.at(a.bufferView);
  const std::size_t stride = v.byteStride ? v.byteStride : components * sizeof(T);
  std::vector<T> out(a.count * components);
  for (std::size_t i = 0; i < a.count; ++i)
    std::memcpy(&out[i * components],
                m.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset + i * stride,
                components * sizeof(T));
  return out;
}

// Back from glTF's y-up to our z-up: (x, y, z)_map = (x, -z, y)_gltf.
Eigen::Vector3d FromYUp(double x, double y, double z) { return {x, -z, y}; }

double SrgbToLinear(int c) {  // IEC 61966-2-1
  const double s = c / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

TEST(GltfWriter, PointsFiveKilometresOutComeBackToAMillimetre) {
  test::ScratchDir dir;
  const std::vector<mapping::MapPoint> points =
      test::MakePoints(2000, Eigen::Vector3d(5000, -3000, 40), 200.0);
  const mapping::VectorPointSource source(points, 300);
  ExportStats stats;
  ASSERT_TRUE(WriteGlb(dir / "map.glb", &source, nullptr, {}, &stats).ok());
  EXPECT_EQ(stats.points_written, 2000u);
  EXPECT_EQ(stats.point_stride, 1u);
  const tinygltf::Model m = LoadGlb(dir / "map.glb");
  ASSERT_EQ(m.nodes.size(), 1u);
  const tinygltf::Node& node = m.nodes[0];
  ASSERT_EQ(node.translation.size(), 3u);
  EXPECT_TRUE(node.rotation.empty());
  const tinygltf::Primitive& prim = m.meshes.at(node.mesh).primitives.at(0);
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_POINTS);
  const tinygltf::Accessor& pos_accessor = m.accessors.at(prim.attributes.at("POSITION"));
  EXPECT_EQ(pos_accessor.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const std::vector<float> pos = AccessorData<float>(m, prim.attributes.at("POSITION"), 3);
  const std::vector<float> col = AccessorData<float>(m, prim.attributes.at("COLOR_0"), 3);
  ASSERT_EQ(pos.size(), 3 * points.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d gltf(node.translation[0] + pos[3 * i], node.translation[1] + pos[3 * i + 1],
                               node.translation[2] + pos[3 * i + 2]);
    const Eigen::Vector3d back = FromYUp(gltf.x(), gltf.y(), gltf.z());
    EXPECT_LT((back - points[i].position).norm(), 1e-3) << i;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min<double>(lo[k], pos[3 * i + k]);
      hi[k] = std::max<double>(hi[k], pos[3 * i + k]);
    }
    const auto& rgb = points[i].has_color ? points[i].rgb : std::array<std::uint8_t, 3>{128, 128, 128};
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(col[3 * i + c], SrgbToLinear(rgb[c]), 1e-6);
  }
  // The y axis of glTF is our up: node translation y is the map's z (~40 m), z is minus the map's y (~3 km).
  EXPECT_NEAR(node.translation[1], 40.0, 101.0);
  EXPECT_NEAR(node.translation[2], 3000.0, 101.0);
  // POSITION min/max are the exact extremes of the stored floats.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(pos_accessor.minValues.at(k), lo[k]);
    EXPECT_EQ(pos_accessor.maxValues.at(k), hi[k]);
  }
}

TEST(GltfWriter, ByteColorsAreTheMapsSrgbBytes) {
  test::ScratchDir dir;
  const std::vector<mapping::MapPoint> points = test::MakePoints(100, Eigen::Vector3d::Zero(), 5.0);
  GltfOptions options;
  options.linear_float_colors = false;
  const mapping::VectorPointSource source(points);
  ASSERT_TRUE(WriteGlb(dir / "bytes.glb", &source, nullptr, options).ok());
  const tinygltf::Model m = LoadGlb(dir / "bytes.glb");
  const tinygltf::Primitive& prim = m.meshes.at(0).primitives.at(0);
  const tinygltf::Accessor& a = m.accessors.at(prim.attributes.at("COLOR_0"));
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE);
  EXPECT_TRUE(a.normalized);
  const std::vector<std::uint8_t> col = AccessorData<std::uint8_t>(m, prim.attributes.at("COLOR_0"), 4);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& rgb = points[i].has_color ? points[i].rgb : std::array<std::uint8_t, 3>{128, 128, 128};
    for (int c = 0; c < 3; ++c) EXPECT_EQ(col[4 * i + c], rgb[c]);
    EXPECT_EQ(col[4 * i + 3], 255);
  }
}

TEST(GltfWriter, SubsamplesAboveMaxPointsAndRecordsTheStride) {
  test::ScratchDir dir;
  std::vector<mapping::MapPoint> points = test::MakePoints(1000, Eigen::Vector3d::Zero(), 5.0);
  points[1].position.x() = std::nan("");  // skipped before striding: finite index k is kept when k % 3 == 0
  GltfOptions options;
  options.max_points = 400;
  ExportStats stats;
  const mapping::VectorPointSource source(points, 64);
  ASSERT_TRUE(WriteGlb(dir / "sub.glb", &source, nullptr, options, &stats).ok());
  EXPECT_EQ(stats.point_stride, 3u);      // ceil(999 / 400)
  EXPECT_EQ(stats.points_written, 333u);  // ceil(999 / 3)
  EXPECT_EQ(stats.points_skipped_nonfinite, 1u);
  const tinygltf::Model m = LoadGlb(dir / "sub.glb");
  const tinygltf::Value& extras = m.asset.extras.Get("ultrafusion");
  EXPECT_EQ(extras.Get("point_stride").GetNumberAsInt(), 3);
  const tinygltf::Node& node = m.nodes.at(0);
  const std::vector<float> pos =
      AccessorData<float>(m, m.meshes[0].primitives[0].attributes.at("POSITION"), 3);
  ASSERT_EQ(pos.size(), 3u * 333u);
  std::vector<std::size_t> finite;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (i != 1) finite.push_back(i);
  for (std::size_t j = 0; j < 333; ++j) {
    const Eigen::Vector3d back =
        FromYUp(node.translation[0] + pos[3 * j], node.translation[1] + pos[3 * j + 1],
                node.translation[2] + pos[3 * j + 2]);
    EXPECT_LT((back - points[finite[3 * j]].position).norm(), 1e-5) << j;
  }
}

TEST(GltfWriter, MeshHasPositionsNormalsColoursAndIndices) {
  test::ScratchDir dir;
  mapping::ColoredMesh mesh;  // a unit square in the plane z = 2, 100 m east, facing up
  mesh.vertices = {{100, 0, 2}, {101, 0, 2}, {101, 1, 2}, {100, 1, 2}};
  mesh.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {10, 20, 30}};
  mesh.normals.assign(4, Eigen::Vector3f(0, 0, 2));  // not unit: the writer normalizes
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  GltfOptions options;
  options.linear_float_colors = false;
  ASSERT_TRUE(WriteGlb(dir / "mesh.glb", nullptr, &mesh, options).ok());
  const tinygltf::Model m = LoadGlb(dir / "mesh.glb");
  const tinygltf::Primitive& prim = m.meshes.at(0).primitives.at(0);
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_TRIANGLES);
  const tinygltf::Node& node = m.nodes.at(0);
  const std::vector<float> pos = AccessorData<float>(m, prim.attributes.at("POSITION"), 3);
  const std::vector<float> nrm = AccessorData<float>(m, prim.attributes.at("NORMAL"), 3);
  const std::vector<std::uint8_t> col = AccessorData<std::uint8_t>(m, prim.attributes.at("COLOR_0"), 4);
  const std::vector<std::uint32_t> idx = AccessorData<std::uint32_t>(m, prim.indices, 1);
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d back =
        FromYUp(node.translation[0] + pos[3 * i], node.translation[1] + pos[3 * i + 1],
                node.translation[2] + pos[3 * i + 2]);
    EXPECT_LT((back - mesh.vertices[i]).norm(), 1e-5);
    EXPECT_EQ(Eigen::Vector3f(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]),
              Eigen::Vector3f(0, 1, 0));  // up = +y
    for (int c = 0; c < 3; ++c) EXPECT_EQ(col[4 * i + c], mesh.colors[i][c]);
  }
  EXPECT_EQ(idx, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  // Counter-clockwise seen from above in the map stays counter-clockwise seen from +y in glTF (a rotation
  // keeps the winding): the triangle's normal from the stored positions points along +y.
  const Eigen::Vector3f p0(pos[0], pos[1], pos[2]), p1(pos[3], pos[4], pos[5]), p2(pos[6], pos[7], pos[8]);
  EXPECT_GT((p1 - p0).cross(p2 - p0).y(), 0.0f);
}

TEST(GltfWriter, RejectsBadMeshesAndEmptyInput) {
  test::ScratchDir dir;
  mapping::ColoredMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.colors = {{1, 2, 3}, {1, 2, 3}, {1, 2, 3}};
  mesh.triangles = {{0, 1, 3}};
  const Status bad_index = WriteGlb(dir / "a.glb", nullptr, &mesh);
  ASSERT_FALSE(bad_index.ok());
  EXPECT_NE(bad_index.message().find("index 3"), std::string::npos) << bad_index.message();
  mesh.triangles = {{0, 1, 2}};
  mesh.colors.pop_back();
  EXPECT_FALSE(WriteGlb(dir / "b.glb", nullptr, &mesh).ok());
  EXPECT_FALSE(WriteGlb(dir / "c.glb", nullptr, nullptr).ok());
  EXPECT_TRUE(dir.Entries().empty());
}

}  // namespace
}  // namespace uf::exporting
