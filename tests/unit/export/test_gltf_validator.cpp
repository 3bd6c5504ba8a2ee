// Runs the Khronos glTF validator on written .glb files (points + mesh, both colour encodings). The
// validator comes from npm (scripts/setup-test-tools installs it into $UF_NPM_TOOLS, default
// ~/.cache/ultrafusion/npm); without node or the validator the test is skipped, saying why.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>

#include "export/gltf_writer.h"
#include "export_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

std::filesystem::path ValidatorModule() {
  const char* tools = std::getenv("UF_NPM_TOOLS");
  const char* home = std::getenv("HOME");
  const std::filesystem::path root =
      tools ? tools : std::filesystem::path(home ? home : "/") / ".cache/ultrafusion/npm";
  return root / "node_modules" / "gltf-validator";
}

bool HaveNode() { return std::system("node --version > /dev/null 2>&1") == 0; }

// Runs the validator; returns its exit status and appends its output to `log`.
int Validate(const std::filesystem::path& glb, std::string& log) {
  const std::string command = "node '" UF_EXPORT_TEST_DIR "/validate_gltf.js' '" +
                              ValidatorModule().string() + "' '" + glb.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 512> line;
  while (fgets(line.data(), line.size(), pipe)) log += line.data();
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(GltfValidator, WrittenGlbHasNoErrorsOrWarnings) {
  if (!HaveNode()) GTEST_SKIP() << "node not found: the Khronos glTF validator cannot run";
  if (!std::filesystem::exists(ValidatorModule() / "package.json"))
    GTEST_SKIP() << "glTF validator not installed at " << ValidatorModule()
                 << ": run scripts/setup-test-tools";

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
