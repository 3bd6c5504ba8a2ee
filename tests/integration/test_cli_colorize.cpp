// `ultrafusion colorize` as a user runs it: the recorded LiDAR-camera pair (coloured fraction, PLY vertex
// count, overlay size), a synthetic pair whose colours are known analytically (our YAML calibration and the
// pair's JSON format, a centred-crop image), and bad input (exit codes, messages, no output file left).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odometry/io/image_decode.h"
#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

namespace fs = std::filesystem;
using test::Ultrafusion;
using testing::TempDir;

// One vertex of a PLY written by uf::exporting::WritePly (position read as double whatever its type).
struct PlyVertex {
  double x = 0, y = 0, z = 0;
  std::uint8_t r = 0, g = 0, b = 0, has_color = 0;
};

// Parses a binary little-endian PLY's `vertex` element from its header's property list.
std::vector<PlyVertex> ReadPly(const std::string& path) {
  const std::string bytes = testing::ReadText(path);
  const std::size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos) << path;
  if (end == std::string::npos) return {};
  std::istringstream header(bytes.substr(0, end));
  std::size_t count = 0;
  std::vector<std::pair<std::string, std::string>> properties;  // type, name
  for (std::string line; std::getline(header, line);) {
    std::istringstream words(line);
    std::string key, a, b;
    words >> key >> a >> b;
    if (key == "element" && a == "vertex") count = std::stoul(b);
    if (key == "property") properties.emplace_back(a, b);
  }
  const auto size_of = [](const std::string& type) {
    return type == "double" ? 8 : type == "float" || type == "uint" || type == "int" ? 4 : 1;
  };
  std::size_t stride = 0;
  for (const auto& [type, name] : properties) stride += size_of(type);
  const char* data = bytes.data() + end + std::strlen("end_header\n");
  EXPECT_EQ(bytes.size() - std::size_t(data - bytes.data()), count * stride) << path;
  std::vector<PlyVertex> vertices(count);
  for (std::size_t i = 0; i < count && count * stride <= bytes.size(); ++i) {
    const char* p = data + i * stride;
    for (const auto& [type, name] : properties) {
      double value = 0;
      if (type == "double") {
        std::memcpy(&value, p, 8);
      } else if (type == "float") {
        float f;
        std::memcpy(&f, p, 4);
        value = f;
      } else if (type == "uchar") {
        value = static_cast<std::uint8_t>(*p);
      }
      PlyVertex& v = vertices[i];
      if (name == "x") v.x = value;
      if (name == "y") v.y = value;
      if (name == "z") v.z = value;
      if (name == "red") v.r = std::uint8_t(value);
      if (name == "green") v.g = std::uint8_t(value);
      if (name == "blue") v.b = std::uint8_t(value);
      if (name == "has_color") v.has_color = std::uint8_t(value);
      p += size_of(type);
    }
  }
  return vertices;
}

// The number printed after `label` in the command's summary table, or -1.
double Printed(const std::string& output, const std::string& label) {
  const std::size_t at = output.find("  " + label + "  ");
  if (at == std::string::npos) return -1;
  const char* text = output.c_str() + at + label.size() + 4;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  return end == text ? -1 : value;
}

Image DecodePngFile(const std::string& path) {
  EncodedImage encoded;
  encoded.format = "png";
  const std::string bytes = testing::ReadText(path);
  encoded.bytes.assign(bytes.begin(), bytes.end());
  Expected<Image> image = DecodeImage(encoded);
  EXPECT_TRUE(image.ok()) << path << ": " << (image.ok() ? "" : image.error());
  return image.ok() ? std::move(image).value() : Image{};
}

// No file left in `folder` (neither an output nor a temporary one).
bool IsEmptyFolder(const fs::path& folder) { return fs::is_empty(folder); }

TEST(CliColorize, RecordedPairColoursTheFootprintAndWritesBothFiles) {
  const std::string data = testing::SharedData();
  if (data.empty())
    GTEST_SKIP() << "../shared/data is absent: the recorded LiDAR-camera pair is not available";
  const std::string pair = data + "/lidar-camera-pair/";
  TempDir out;
  const auto result =
      Ultrafusion("colorize " + pair + "scan.pcd " + pair + "image.png --intrinsics " + pair +
                  "camera_intrinsic.json --extrinsic " + pair + "lidar_to_camera_extrinsic.json --out " +
                  out.File("scan.ply") + " --overlay " + out.File("overlay.png"));
  ASSERT_EQ(result.code, 0) << result.output;
  std::printf("%s", result.output.c_str());
  // The intrinsics are for 1920x1080, the image is 1920x1200: a centred crop, cy moves by +60 rows.
  EXPECT_NE(result.output.find("centred crop"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("(+0.0, +60.0) px"), std::string::npos) << result.output;
  EXPECT_EQ(Printed(result.output, "points in the scan"), 78238);
  EXPECT_GT(Printed(result.output, "in front of the camera, inside the image"), 9000);
  EXPECT_GE(Printed(result.output, "coloured fraction"), 95.0) << result.output;
  EXPECT_GT(Printed(result.output, "edge-alignment score"), 1.0) << result.output;

  const std::string ply = testing::ReadText(out.File("scan.ply"));
  EXPECT_NE(ply.find("element vertex 78238\n"), std::string::npos);
  const Image overlay = DecodePngFile(out.File("overlay.png"));
  EXPECT_EQ(overlay.width, 1920);
  EXPECT_EQ(overlay.height, 1200);
  EXPECT_EQ(overlay.channels, 3);
}

// A synthetic rig: LiDAR frame = body frame; the camera looks along the LiDAR's x axis from (0.3, 0, 0)
// (camera x right = -y, camera y down = -z), so p_cam = (-y, -z, x - 0.3) and, with fx = fy = 50,
// cx = 39.5, cy = 29.5: u = 39.5 - 50 y / (x - 0.3), v = 29.5 - 50 z / (x - 0.3). The 80x60 image holds
// 20x20-pixel blocks of known colours.
constexpr int kWidth = 80, kHeight = 60, kBlock = 20;

std::array<std::uint8_t, 3> BlockColor(int block_u, int block_v) {
  return {std::uint8_t(40 + 60 * block_u), std::uint8_t(30 + 90 * block_v), std::uint8_t(200 - 50 * block_u)};
}

// The block pattern as a PNG of `rows` rows: the calibrated 60 rows in the middle, black rows around them.
std::string WriteBlockImage(const TempDir& dir, const std::string& name, int rows) {
  Image image{kWidth, rows, 3, std::vector<std::uint8_t>(std::size_t(kWidth) * rows * 3, 0)};
  const int top = (rows - kHeight) / 2;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      const auto color = BlockColor(u / kBlock, v / kBlock);
      std::copy(color.begin(), color.end(),
                image.pixels.begin() + 3 * (std::ptrdiff_t(v + top) * kWidth + u));
    }
  auto png = EncodePng(image, name);
  EXPECT_TRUE(png.ok());
  return dir.Write(name, std::string(png->begin(), png->end()));
}

struct SyntheticPoint {
  float x, y, z;
};

// A wall at x = 5 m filling the view (0.1 m grid, about 1 px apart), a patch of a wall at x = 10.3 m
// behind it (occluded), points beside the view (|y| = 5 m at x = 5 m: u < -0.5 or u > 79.5) and behind
// the LiDAR (x = -5 m).
std::vector<SyntheticPoint> SyntheticScan() {
  std::vector<SyntheticPoint> points;
  for (int i = -29; i <= 29; ++i)
    for (int j = -19; j <= 19; ++j) points.push_back({5.0f, 0.1f * i, 0.1f * j});
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) points.push_back({10.3f, 0.2f * i, 0.2f * j});
  for (int j = -5; j <= 5; ++j) {
    points.push_back({5.0f, 5.0f, 0.2f * j});
    points.push_back({5.0f, -5.0f, 0.2f * j});
    points.push_back({-5.0f, 0.1f * j, 0.1f * j});
  }
  return points;
}

std::string WritePcd(const TempDir& dir, const std::vector<SyntheticPoint>& points) {
  std::ostringstream text;
  text.precision(9);  // float values read back exactly
  text << "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH "
       << points.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.size()
       << "\nDATA ascii\n";
  for (const SyntheticPoint& p : points) text << p.x << " " << p.y << " " << p.z << " 7\n";
  return dir.Write("scan.pcd", text.str());
}

std::string WriteYamlCalibration(const TempDir& dir) {
  return dir.Write("calibration.yaml", R"(calibration:
  body_frame: lidar
  sensors:
    - name: lidar
      kind: lidar
      T_body_sensor: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    - name: cam0
      kind: camera
      T_body_sensor: [0, 0, 1, 0.3, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0, 1]
      intrinsics:
        distortion_model: radial-tangential
        intrinsics: [50, 50, 39.5, 29.5]
        distortion_coefficients: [0, 0, 0, 0]
        resolution: [80, 60]
)");
}

// The same rig as a dataset folder's dataset.yaml (with the stream files it names, empty).
std::string WriteDatasetYaml(const TempDir& dir) {
  fs::create_directories(dir.path() / "dataset" / "cam0");
  dir.Write("dataset/lidar.bin", "");
  dir.Write("dataset/cam0/cam0.csv", "# stamp_ns,filename\n");
  return dir.Write("dataset/dataset.yaml", R"(format: ultrafusion-dataset
version: 1
streams:
  - name: velodyne
    kind: lidar
    file: lidar.bin
    T_body_sensor: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
  - name: cam0
    kind: camera
    file: cam0/cam0.csv
    camera: 0
    T_body_sensor: [0, 0, 1, 0.3, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0, 1]
    calibration:
      distortion_model: radial-tangential
      intrinsics: [50, 50, 39.5, 29.5]
      distortion_coefficients: [0, 0, 0, 0]
      resolution: [80, 60]
)");
}

// The scan as a KITTI Velodyne .bin: float32 x y z intensity per point, little-endian.
std::string WriteKittiBin(const TempDir& dir, const std::vector<SyntheticPoint>& points) {
  std::string bytes;
  for (const SyntheticPoint& p : points)
    for (const float value : {p.x, p.y, p.z, 7.0f}) bytes.append(reinterpret_cast<const char*>(&value), 4);
  return dir.Write("scan.bin", bytes);
}

// The same rig in the recorded pair's JSON layout; T_cam_lidar = T_body_cam^-1 (rows of R^T, -R^T t).
const char* kIntrinsicJson = R"({"cam-intrinsic": {"param": {"img_dist_w": 80, "img_dist_h": 60,
  "cam_K": {"data": [[50, 0, 39.5], [0, 50, 29.5], [0, 0, 1]]}, "cam_dist": {"data": [[0, 0, 0, 0]]}}}})";
const char* kExtrinsicJson = R"({"lidar-to-cam-extrinsic": {"param": {"sensor_calib": {"data":
  [[0, -1, 0, 0], [0, 0, -1, 0], [1, 0, 0, -0.3], [0, 0, 0, 1]]}}}})";

// Checks every vertex of the synthetic run against the analytic projection.
void CheckSyntheticColours(const std::vector<PlyVertex>& vertices,
                           const std::vector<SyntheticPoint>& points) {
  ASSERT_EQ(vertices.size(), points.size());
  std::size_t checked = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SyntheticPoint& p = points[i];
    const PlyVertex& v = vertices[i];
    EXPECT_NEAR(v.x, p.x, 1e-6);
    EXPECT_NEAR(v.y, p.y, 1e-6);
    const double u = 39.5 - 50.0 * p.y / (p.x - 0.3), row = 29.5 - 50.0 * p.z / (p.x - 0.3);
    const bool in_view = p.x > 0.3 && u > -0.5 && u < kWidth - 0.5 && row > -0.5 && row < kHeight - 0.5;
    if (!in_view || p.x > 10) {  // outside the footprint, or behind the near wall
      EXPECT_EQ(v.has_color, 0) << "point " << i;
      continue;
    }
    ASSERT_EQ(v.has_color, 1) << "point " << i;
    // Bilinear sampling reads pixels floor(u) and floor(u) + 1: one block when both lie in it.
    const auto same_block = [](double c) {
      const int lo = std::max(0, int(std::floor(c)));
      return lo / kBlock == std::min(lo + 1, kWidth - 1) / kBlock;
    };
    if (!same_block(u) || !same_block(row)) continue;
    const auto expected = BlockColor(int(std::floor(u)) / kBlock, std::max(0, int(std::floor(row))) / kBlock);
    EXPECT_EQ(v.r, expected[0]) << "point " << i << " at pixel " << u << ", " << row;
    EXPECT_EQ(v.g, expected[1]) << "point " << i;
    EXPECT_EQ(v.b, expected[2]) << "point " << i;
    ++checked;
  }
  EXPECT_GT(checked, 1500u);  // most of the 2301 wall points lie inside a block
}

TEST(CliColorize, SyntheticPairFromYamlCalibrationGetsTheImageColours) {
  TempDir dir;
  const std::vector<SyntheticPoint> points = SyntheticScan();
  const std::string arguments =
      "colorize " + WritePcd(dir, points) + " " + WriteBlockImage(dir, "image.png", 60);
  const std::string yaml = WriteYamlCalibration(dir);
  const auto result = Ultrafusion(arguments + " --intrinsics " + yaml + " --extrinsic " + yaml + " --out " +
                                  dir.File("out.ply") + " --overlay " + dir.File("overlay.png"));
  ASSERT_EQ(result.code, 0) << result.output;
  // Analytic counts: 59 x 39 wall points and 11 x 11 behind it in the view, all of them in front.
  EXPECT_EQ(Printed(result.output, "points in the scan"), double(points.size()));
  EXPECT_EQ(Printed(result.output, "in front of the camera"), double(points.size() - 11));
  EXPECT_EQ(Printed(result.output, "in front of the camera, inside the image"), 59 * 39 + 121);
  EXPECT_EQ(Printed(result.output, "coloured (visible)"), 59 * 39);
  EXPECT_EQ(Printed(result.output, "occluded (behind nearer points)"), 121);
  EXPECT_EQ(result.output.find("centred crop"), std::string::npos);  // image of the calibrated size
  CheckSyntheticColours(ReadPly(dir.File("out.ply")), points);
  const Image overlay = DecodePngFile(dir.File("overlay.png"));
  EXPECT_EQ(overlay.width, kWidth);
  EXPECT_EQ(overlay.height, kHeight);

  // The same rig from a dataset.yaml, and the same scan as a KITTI .bin: the same PLY, byte for byte.
  const std::string dataset = WriteDatasetYaml(dir);
  const auto from_dataset = Ultrafusion(arguments + " --intrinsics " + dataset + " --extrinsic " + dataset +
                                        " --out " + dir.File("dataset.ply"));
  ASSERT_EQ(from_dataset.code, 0) << from_dataset.output;
  EXPECT_TRUE(testing::ReadText(dir.File("dataset.ply")) == testing::ReadText(dir.File("out.ply")));
  const auto from_bin =
      Ultrafusion("colorize " + WriteKittiBin(dir, points) + " " + dir.File("image.png") + " --intrinsics " +
                  yaml + " --extrinsic " + yaml + " --out " + dir.File("bin.ply"));
  ASSERT_EQ(from_bin.code, 0) << from_bin.output;
  EXPECT_TRUE(testing::ReadText(dir.File("bin.ply")) == testing::ReadText(dir.File("out.ply")));
}

TEST(CliColorize, SyntheticPairFromJsonWithACroppedImageGetsTheSameColours) {
  TempDir dir;
  const std::vector<SyntheticPoint> points = SyntheticScan();
  // 70 rows: the calibrated 60 and 5 more above and below, so cy moves from 29.5 to 34.5.
  const auto result =
      Ultrafusion("colorize " + WritePcd(dir, points) + " " + WriteBlockImage(dir, "image.png", 70) +
                  " --intrinsics " + dir.Write("intrinsic.json", kIntrinsicJson) + " --extrinsic " +
                  dir.Write("extrinsic.json", kExtrinsicJson) + " --out " + dir.File("out.ply"));
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("(+0.0, +5.0) px"), std::string::npos) << result.output;
  CheckSyntheticColours(ReadPly(dir.File("out.ply")), points);
}

// Runs colorize on the synthetic pair with one input replaced; expects `code`, a message holding `message`
// and no file in the output folder.
void ExpectFailure(const std::string& scan, const std::string& image, const std::string& intrinsics,
                   const std::string& extrinsic, const fs::path& out, int code, const std::string& message) {
  const auto result = Ultrafusion("colorize " + scan + " " + image + " --intrinsics " + intrinsics +
                                  " --extrinsic " + extrinsic + " --out " + (out / "out.ply").string() +
                                  " --overlay " + (out / "overlay.png").string());
  EXPECT_EQ(result.code, code) << result.output;
  EXPECT_NE(result.output.find(message), std::string::npos) << "expected '" << message << "' in\n"
                                                            << result.output;
  if (fs::exists(out)) {
    EXPECT_TRUE(IsEmptyFolder(out)) << "a file was left in " << out;
  }
}

TEST(CliColorize, BadInputGivesAClearErrorAndNoOutputFile) {
  TempDir dir;
  const std::string scan = WritePcd(dir, SyntheticScan());
  const std::string image = WriteBlockImage(dir, "image.png", 60);
  const std::string yaml = WriteYamlCalibration(dir);
  const std::string intrinsics = dir.Write("intrinsic.json", kIntrinsicJson);
  const std::string extrinsic = dir.Write("extrinsic.json", kExtrinsicJson);
  const fs::path out = dir.path() / "out";
  fs::create_directories(out);

  const std::string corrupt = dir.Write("corrupt.png", "\x89PNG\r\n\x1a\nthis is not a PNG stream");
  ExpectFailure(scan, corrupt, yaml, yaml, out, 1, "corrupt.png: cannot be decoded");
  ExpectFailure(scan, dir.File("missing.png"), yaml, yaml, out, 1, "missing.png: cannot be read");
  ExpectFailure(dir.Write("broken.pcd", "VERSION .7\nFIELDS x y\n"), image, yaml, yaml, out, 1, "broken.pcd");
  std::string no_k = kIntrinsicJson;
  no_k.replace(no_k.find("cam_K"), 5, "cam_Q");
  ExpectFailure(scan, image, dir.Write("no_k.json", no_k), extrinsic, out, 1, "no_k.json");
  ExpectFailure(scan, image, dir.Write("bad.json", "{\"cam-intrinsic\": "), extrinsic, out, 1,
                "bad.json: not valid JSON");
  std::string bad_w = kIntrinsicJson;
  bad_w.replace(bad_w.find("80"), 2, "-8");
  ExpectFailure(scan, image, dir.Write("bad_w.json", bad_w), extrinsic, out, 1,
                "cam-intrinsic.param.img_dist_w: expected a whole number of pixels");
  ExpectFailure(scan, image, intrinsics, dir.Write("wrong.yaml", "calibration:\n  sensors: 3\n"), out, 1,
                "wrong.yaml");
  // The camera turned round (T_cam_lidar with x -> -z): no point in front of it.
  std::string backwards = kExtrinsicJson;
  backwards.replace(backwards.find("[1, 0, 0, -0.3]"), 15, "[-1, 0, 0, 0.3]");
  backwards.replace(backwards.find("[0, -1, 0, 0]"), 13, "[0, 1, 0, 0]");  // keeps det = +1
  ExpectFailure(dir.Write("scan_front.pcd",
                          "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                          "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n5 0 0\n6 1 0\n"),
                image, intrinsics, dir.Write("backwards.json", backwards), out, 1, "in front of the camera");
  // The output folder does not exist: nothing is written, the overlay neither.
  ExpectFailure(scan, image, yaml, yaml, out / "missing", 1, "missing");
  EXPECT_TRUE(IsEmptyFolder(out));

  // Usage errors: unknown extension, missing option, wrong output extension.
  ExpectFailure(dir.Write("scan.xyz", "1 2 3\n"), image, yaml, yaml, out, 2, "expected a .pcd or KITTI .bin");
  ExpectFailure(scan, image, dir.Write("calib.txt", ""), yaml, out, 2, "--intrinsics");
  const auto missing = Ultrafusion("colorize " + scan + " " + image + " --intrinsics " + yaml + " --out " +
                                   (out / "out.ply").string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("--extrinsic"), std::string::npos) << missing.output;
  const auto not_ply = Ultrafusion("colorize " + scan + " " + image + " --intrinsics " + yaml +
                                   " --extrinsic " + yaml + " --out " + (out / "out.las").string());
  EXPECT_EQ(not_ply.code, 2) << not_ply.output;
  EXPECT_TRUE(IsEmptyFolder(out));
}

}  // namespace
}  // namespace uf
