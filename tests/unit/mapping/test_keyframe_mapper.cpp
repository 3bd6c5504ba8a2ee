// KeyframeMapper against hand-built scenes: a camera frame between two keyframes is placed at the
// interpolated body pose, so each point of a plane takes the colour of the pixel it was built on (and not
// that of the keyframe's own pose, 10 px away); frames farther than max_frame_distance_s from a keyframe are
// not used (nor decoded); cameras without intrinsics or extrinsic give a warning and an uncoloured map;
// frames that fail to decode, or have the wrong size, are skipped with a warning.
#include <gtest/gtest.h>

#include <vector>

#include "mapping/keyframe_mapper.h"
#include "mapping/map_view.h"

namespace uf::mapping {
namespace {

constexpr int kWidth = 64, kHeight = 48;
constexpr double kF = 50.0, kCx = 31.5, kCy = 23.5;
constexpr double kDepth = 5.0;  // m, the plane z = 5 in the world
constexpr int kCameraStream = 1;

// A colour that differs for every pixel.
Rgb PixelColor(int u, int v) {
  return {static_cast<std::uint8_t>(3 * u), static_cast<std::uint8_t>(5 * v), std::uint8_t{7}};
}

CameraFrame PatternFrame(double seconds) {
  CameraFrame frame;
  frame.stamp = FromSeconds(seconds);
  frame.image = Image{kWidth, kHeight, 3, std::vector<std::uint8_t>(kWidth * kHeight * 3)};
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
      for (int c = 0; c < 3; ++c) frame.image.pixels[(v * kWidth + u) * 3 + c] = PixelColor(u, v)[c];
  return frame;
}

// A frame whose bytes are no image.
CameraFrame UndecodableFrame(double seconds) {
  CameraFrame frame;
  frame.stamp = FromSeconds(seconds);
  frame.encoded.format = "png";
  frame.encoded.bytes = {1, 2, 3};
  return frame;
}

// A LiDAR stream and one camera whose frame is the body's (OpenCV axes: it looks along the body's z).
DatasetDescription Description(bool intrinsics = true, bool extrinsic = true) {
  DatasetDescription description;
  description.streams.resize(2);
  description.streams[0].name = "lidar";
  description.streams[0].kind = SensorKind::kLidar;
  StreamInfo& camera = description.streams[kCameraStream];
  camera.name = "cam0";
  camera.kind = SensorKind::kCamera;
  if (intrinsics)
    camera.camera_model =
        std::make_shared<PinholeRadtan>(PinholeRadtanIntrinsics{{kWidth, kHeight, kF, kF, kCx, kCy}});
  if (extrinsic) camera.T_body_sensor = SE3();
  return description;
}

KeyframeMapperOptions Options(double max_frame_distance_s) {
  KeyframeMapperOptions options;
  options.map.min_observations = 1;  // every inserted point shows in the view
  options.colorizer.max_time_difference_s = 1.0;
  options.max_frame_distance_s = max_frame_distance_s;
  return options;
}

// The camera (= body) centre at frame time 0.4 s, halfway between the keyframes at (0, 0, 0) and (2, 0, 0).
const Eigen::Vector3d kCameraAtFrame(1, 0, 0);

// The world point on the plane seen at pixel (u, v) from kCameraAtFrame.
Eigen::Vector3f PointAtPixel(int u, int v) {
  return (kCameraAtFrame + Eigen::Vector3d((u - kCx) / kF * kDepth, (v - kCy) / kF * kDepth, kDepth))
      .cast<float>();
}

struct Scene {
  std::vector<Eigen::Vector2i> pixels;
  Keyframe first, second;  // at 0 s and 0.8 s; the points belong to the first
};

Scene MakeScene() {
  Scene scene;
  for (int v = 4; v < kHeight - 4; v += 4)
    for (int u = 12; u < kWidth - 4; u += 4) scene.pixels.emplace_back(u, v);
  scene.first.stamp = 0;
  for (const Eigen::Vector2i& pixel : scene.pixels) {
    scene.first.scan_world.push_back(PointAtPixel(pixel.x(), pixel.y()));
    scene.first.scan_intensity.push_back(1);
  }
  scene.second.stamp = FromSeconds(0.8);
  scene.second.T_world_body = SE3(SO3(), Eigen::Vector3d(2, 0, 0));
  return scene;
}

// Feeds the keyframes with `frame` between them, as the stream delivers them, and finishes.
KeyframeMapper MapScene(const Scene& scene, const KeyframeMapperOptions& options,
                        const DatasetDescription& description, std::vector<CameraFrame> frames) {
  Expected<KeyframeMapper> mapper = KeyframeMapper::Create(options, description, SE3());
  EXPECT_TRUE(mapper.ok()) << mapper.error();
  EXPECT_TRUE(mapper->AddKeyframe(scene.first).ok());
  for (CameraFrame& frame : frames) mapper->AddCameraFrame(kCameraStream, std::move(frame));
  EXPECT_TRUE(mapper->AddKeyframe(scene.second).ok());
  EXPECT_TRUE(mapper->Finish().ok());
  return std::move(*mapper);
}

std::size_t ColouredMapPoints(const KeyframeMapper& mapper) {
  std::size_t coloured = 0;
  MapView(mapper.map(), {.compute_normals = false}).ForEachChunk([&](std::span<const MapPoint> chunk) {
    for (const MapPoint& point : chunk) coloured += point.has_color;
    return true;
  });
  return coloured;
}

TEST(KeyframeMapper, AFrameBetweenKeyframesIsPlacedAtTheInterpolatedPose) {
  const Scene scene = MakeScene();
  const KeyframeMapper mapper = MapScene(scene, Options(0.5), Description(), {PatternFrame(0.4)});
  EXPECT_TRUE(mapper.warnings().empty());
  EXPECT_EQ(mapper.in_footprint_points(), scene.pixels.size());
  EXPECT_EQ(mapper.colored_points(), scene.pixels.size());
  const MapView view(mapper.map(), {.compute_normals = false});
  ASSERT_EQ(view.size(), scene.pixels.size());
  for (const Eigen::Vector2i& pixel : scene.pixels) {
    const std::optional<MapPoint> point =
        view.Nearest(PointAtPixel(pixel.x(), pixel.y()).cast<double>(), 0.01);
    ASSERT_TRUE(point.has_value()) << pixel.transpose();
    ASSERT_TRUE(point->has_color) << pixel.transpose();
    // With the first keyframe's pose instead (camera at the origin) the colour would come from 10 px to
    // the right: u + kF * 1 m / kDepth.
    EXPECT_EQ(point->rgb, PixelColor(pixel.x(), pixel.y())) << pixel.transpose();
  }
}

TEST(KeyframeMapper, AKeyframeIsColouredFromFramesBeyondItsNeighbours) {
  // The points belong to a keyframe at 0 s; the only frame, at 0.4 s, lies between two later keyframes
  // (0.3 s and 0.5 s, the body moving 2.5 m/s along x), within the 0.5 s reach: its pose is interpolated
  // between those two, and it colours the first keyframe's points.
  Scene scene = MakeScene();
  Keyframe at_03, at_05, at_09;
  at_03.stamp = FromSeconds(0.3), at_03.T_world_body = SE3(SO3(), Eigen::Vector3d(0.75, 0, 0));
  at_05.stamp = FromSeconds(0.5), at_05.T_world_body = SE3(SO3(), Eigen::Vector3d(1.25, 0, 0));
  at_09.stamp = FromSeconds(0.9), at_09.T_world_body = SE3(SO3(), Eigen::Vector3d(2.25, 0, 0));
  Expected<KeyframeMapper> mapper = KeyframeMapper::Create(Options(0.5), Description(), SE3());
  ASSERT_TRUE(mapper.ok()) << mapper.error();
  ASSERT_TRUE(mapper->AddKeyframe(scene.first).ok());
  ASSERT_TRUE(mapper->AddKeyframe(at_03).ok());
  mapper->AddCameraFrame(kCameraStream, PatternFrame(0.4));
  ASSERT_TRUE(mapper->AddKeyframe(at_05).ok());
  ASSERT_TRUE(mapper->AddKeyframe(at_09).ok());  // 0.9 s: the first keyframe's window is complete
  EXPECT_EQ(mapper->colored_points(), scene.pixels.size());
  ASSERT_TRUE(mapper->Finish().ok());
  const MapView view(mapper->map(), {.compute_normals = false});
  for (const Eigen::Vector2i& pixel : scene.pixels) {
    const std::optional<MapPoint> point =
        view.Nearest(PointAtPixel(pixel.x(), pixel.y()).cast<double>(), 0.01);
    ASSERT_TRUE(point.has_value() && point->has_color) << pixel.transpose();
    EXPECT_EQ(point->rgb, PixelColor(pixel.x(), pixel.y())) << pixel.transpose();
  }
}

TEST(KeyframeMapper, FramesFartherThanTheMaximumDistanceAreNotUsed) {
  const Scene scene = MakeScene();
  // 0.4 s from both keyframes, beyond 0.3 s. The undecodable frame at 0.45 s is never decoded, so it gives
  // no warning either.
  const KeyframeMapper mapper =
      MapScene(scene, Options(0.3), Description(), {PatternFrame(0.4), UndecodableFrame(0.45)});
  EXPECT_TRUE(mapper.warnings().empty());
  EXPECT_EQ(mapper.colored_points(), 0u);
  EXPECT_EQ(mapper.map().size(), scene.pixels.size());
  EXPECT_EQ(ColouredMapPoints(mapper), 0u);
}

TEST(KeyframeMapper, AFrameAfterTheLastKeyframeIsNotExtrapolatedTo) {
  Scene scene = MakeScene();
  std::swap(scene.first.scan_world, scene.second.scan_world);  // the points now belong to the last keyframe
  std::swap(scene.first.scan_intensity, scene.second.scan_intensity);
  Expected<KeyframeMapper> mapper = KeyframeMapper::Create(Options(0.5), Description(), SE3());
  ASSERT_TRUE(mapper.ok());
  ASSERT_TRUE(mapper->AddKeyframe(scene.first).ok());
  ASSERT_TRUE(mapper->AddKeyframe(scene.second).ok());
  mapper->AddCameraFrame(kCameraStream, PatternFrame(1.0));  // 0.2 s after the last keyframe
  ASSERT_TRUE(mapper->Finish().ok());
  EXPECT_EQ(mapper->colored_points(), 0u);
  EXPECT_EQ(ColouredMapPoints(*mapper), 0u);
}

TEST(KeyframeMapper, CamerasWithoutIntrinsicsOrExtrinsicLeaveTheMapUncoloured) {
  const Scene scene = MakeScene();
  for (const bool intrinsics : {false, true}) {
    const DatasetDescription description = Description(intrinsics, !intrinsics);
    Expected<KeyframeMapper> created = KeyframeMapper::Create(Options(0.5), description, SE3());
    ASSERT_TRUE(created.ok());
    EXPECT_FALSE(created->UsesCamera(kCameraStream));
    const KeyframeMapper mapper = MapScene(scene, Options(0.5), description, {PatternFrame(0.4)});
    const std::vector<std::string> expected = {std::string("camera cam0 has no ") +
                                                   (intrinsics ? "extrinsic (T_body_sensor)" : "intrinsics") +
                                                   ": it does not colour the map",
                                               "no calibrated camera: the map is written without colour"};
    EXPECT_EQ(mapper.warnings(), expected);
    EXPECT_EQ(mapper.map().size(), scene.pixels.size());
    EXPECT_EQ(ColouredMapPoints(mapper), 0u);
  }
}

TEST(KeyframeMapper, FramesThatFailToDecodeAreSkippedWithAWarning) {
  const Scene scene = MakeScene();
  CameraFrame wrong_size;
  wrong_size.stamp = FromSeconds(0.3);
  wrong_size.image = Image{10, 10, 3, std::vector<std::uint8_t>(300)};
  const KeyframeMapper mapper =
      MapScene(scene, Options(0.5), Description(), {std::move(wrong_size), UndecodableFrame(0.4)});
  ASSERT_EQ(mapper.warnings().size(), 2u);
  EXPECT_EQ(mapper.warnings()[0].rfind("camera frame at 0.300000 s not used: ", 0), 0u)
      << mapper.warnings()[0];
  EXPECT_EQ(mapper.warnings()[1].rfind("camera frame at 0.400000 s not used: ", 0), 0u)
      << mapper.warnings()[1];
  EXPECT_EQ(mapper.colored_points(), 0u);
  EXPECT_EQ(mapper.map().size(), scene.pixels.size());
  EXPECT_EQ(ColouredMapPoints(mapper), 0u);
}

}  // namespace
}  // namespace uf::mapping
