#include "viewer/pipeline/colorize/colorize_job.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "export/ply_writer.h"
#include "mapping/point_source.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/image_decode.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;

// The PLY's points: every scan point, coloured or not (has_color tells), one observation each.
mapping::VectorPointSource ToPointSource(const ColorizeScan& scan, const mapping::ColorizeResult& colors) {
  std::vector<mapping::MapPoint> points(scan.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    mapping::MapPoint& p = points[i];
    p.position = scan.points[i].cast<double>();
    p.intensity = scan.intensities[i];
    p.count = 1;
    p.last_stamp = scan.stamp;
    if (colors.colors[i]) {
      p.rgb = *colors.colors[i];
      p.has_color = true;
    }
  }
  return mapping::VectorPointSource(std::move(points));
}

}  // namespace

Status WriteColorizeOutputs(const std::string& out_path, const std::string& overlay_path,
                            const ColorizeScan& scan, const ColorizeSummary& summary) {
  const std::optional<Image>& overlay = summary.overlay;
  std::unique_ptr<AtomicFileWriter> overlay_file;
  if (overlay) {
    auto png = EncodePng(*overlay, overlay_path);
    if (!png) return png.status();
    overlay_file = std::make_unique<AtomicFileWriter>(overlay_path);
    if (Status s = overlay_file->status(); !s.ok()) return s;
    overlay_file->stream().write(reinterpret_cast<const char*>(png->data()), std::streamsize(png->size()));
  }
  if (Status s = exporting::WritePly(out_path, ToPointSource(scan, summary.colors)); !s.ok()) return s;
  if (overlay_file) {
    if (Status s = overlay_file->Commit(); !s.ok()) {
      std::error_code ignored;
      fs::remove(out_path, ignored);  // neither output rather than half of them
      return s;
    }
  }
  return Status();
}

Expected<FittedCamera> CameraForImage(const LoadedIntrinsics& intrinsics, const Image& image,
                                      const std::string& path) {
  const CameraModel& calibrated = *intrinsics.camera;
  const int w = calibrated.width(), h = calibrated.height();
  if (w == image.width && h == image.height) return FittedCamera{intrinsics.camera, "", ""};
  Eigen::Vector2d shift;
  auto fitted = FitCameraToImage(calibrated, image.width, image.height, &shift);
  if (!fitted) return Status::Error(path + ": " + fitted.error());
  const bool larger = image.width >= w && image.height >= h, smaller = image.width <= w && image.height <= h;
  char text[96];
  std::snprintf(text, sizeof(text), ", principal point shifted by (%+.1f, %+.1f) px", shift.x(), shift.y());
  FittedCamera camera{*fitted, "", ""};
  camera.note = "calibrated for " + std::to_string(w) + "x" + std::to_string(h) + ", the image is " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + ": " +
                (larger    ? "the calibrated image taken as its centred crop"
                 : smaller ? "taken as a centred crop of the calibrated image"
                           : "taken as a centred crop (centres aligned)") +
                text;
  if (std::abs(image.width - w) > w / 4 || std::abs(image.height - h) > h / 4)
    camera.warning =
        "the image and calibrated sizes differ by more than 25 %: if the image was scaled rather than "
        "cropped, " +
        path + " does not fit it";
  return camera;
}

Expected<ColorizeSummary> ColorizeWithImage(const ColorizeScan& scan, const Image& image,
                                            const CameraModel& camera, const SE3& T_cam_lidar, bool overlay,
                                            const ColorizeFileNames& names) {
  // The LiDAR frame is the world frame: T_world_cam = T_lidar_cam = T_cam_lidar^-1.
  const SE3 T_world_cam = T_cam_lidar.inverse();
  const SE3 T_cam_world = T_cam_lidar;
  ColorizeSummary summary;
  summary.points = scan.points.size();
  for (const Eigen::Vector3f& p : scan.points)
    if ((T_cam_world * p.cast<double>()).z() > CameraModel::kMinDepth) ++summary.in_front;
  if (summary.in_front == 0)
    return Status::Error("no point of " + names.scan + " is in front of the camera: check that " +
                         names.extrinsic + " maps LiDAR points into the camera frame (T_cam_lidar)");

  const mapping::ColorizerOptions options;
  const mapping::CameraView view{&image, &camera, T_world_cam, scan.stamp};
  auto colors = mapping::Colorize(scan.points, std::span(&scan.stamp, 1), std::span(&view, 1), options);
  if (!colors) return colors.status();
  summary.colors = std::move(*colors);
  if (summary.colors.in_footprint == 0)
    return Status::Error("none of the " + std::to_string(summary.in_front) +
                         " points in front of the camera projects into the image: check the intrinsics and "
                         "the extrinsic");

  mapping::EdgeAlignmentOptions edge_options;
  edge_options.visibility = options.visibility;
  const mapping::ProjectedScan projected =
      mapping::ProjectWithOcclusion(scan.points, camera, T_world_cam, options.visibility);
  summary.edges = mapping::EdgeAlignmentScorer(image, edge_options).Score(projected);

  if (overlay) {
    summary.depth_range = VisibleDepthRange(projected);
    summary.overlay = RenderDepthOverlay(image, projected, summary.depth_range);
  }
  return summary;
}

}  // namespace uf::pipeline
