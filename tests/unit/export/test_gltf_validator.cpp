// Runs the Khronos glTF validator on written .glb files (points + mesh, both colour encodings). The
// validator comes from npm (scripts/setup-test-tools installs it into $UF_NPM_TOOLS, default
// ~/.cache/ultrafusion/npm); without node or the validator the test is skipped, saying why.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>

#include "export/gltf_writer.h"
#include "export_test_util.h"
#include "gltf_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

using test::Validate;

TEST(GltfValidator, WrittenGlbHasNoErrorsOrWarnings) {
  if (const std::string why = test::ValidatorUnavailable(); !why.empty()) GTEST_SKIP() << why;

  test::ScratchDir dir;
  std::vector<mapping::MapPoint> points = test::MakePoints(5000, Eigen::Vector3d(5000, 2000, 30), 100.0);
  points[10].position.x() = std::nan("");
  const mapping::VectorPointSource source(points);
  mapping::ColoredMesh mesh;  // a small grid, normals up, one uncoloured-grey corner
  const int n = 10;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      mesh.vertices.emplace_back(5000 + x, 2000 + y, 0.1 * x);
      mesh.colors.push_back({std::uint8_t(20 * x), std::uint8_t(20 * y), 128});
      mesh.normals.push_back(Eigen::Vector3f(-0.1f, 0, 1).normalized());
    }
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const std::uint32_t i = y * n + x;
      mesh.triangles.push_back({i, i + 1, i + n + 1});
      mesh.triangles.push_back({i, i + n + 1, i + n});
    }
  const Georeference georef = Georeference::Create({48.1, 11.5, 520.0}).value();
  for (const bool linear : {true, false}) {
    for (const OutputCrs crs : {OutputCrs::kLocal, OutputCrs::kUtm}) {
      GltfOptions options;
      options.linear_float_colors = linear;
      options.crs = crs;
      options.georef = &georef;
      options.max_points = 3000;  // subsampled
      const std::filesystem::path glb =
          dir / (std::string("map_") + OutputCrsName(crs) + (linear ? "_f" : "_b") + ".glb");
      ASSERT_TRUE(WriteGlb(glb, &source, &mesh, options).ok());
      std::string log;
      const int status = Validate(glb, log);
      ASSERT_NE(status, 2) << log;
      EXPECT_EQ(status, 0) << log;
      EXPECT_NE(log.find(" 0 errors, 0 warnings"), std::string::npos) << log;
    }
  }
}

}  // namespace
}  // namespace uf::exporting
