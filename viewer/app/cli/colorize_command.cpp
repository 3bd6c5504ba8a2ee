#include "viewer/app/cli/colorize_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "export/ply_writer.h"
#include "mapping/colorize_edge_alignment.h"
#include "mapping/colorizer.h"
#include "mapping/point_source.h"
#include "odometry/io/atomic_file.h"
#include "odometry/io/image_decode.h"
#include "viewer/pipeline/colorize/colorize_calibration.h"
#include "viewer/pipeline/colorize/colorize_inputs.h"
#include "viewer/pipeline/colorize/colorize_overlay.h"
#include "viewer/app/cli/exit_codes.h"

namespace uf::app {

using pipeline::ColorizeScan;
using pipeline::DepthRange;
using pipeline::FitCameraToImage;
using pipeline::IsCalibrationExtension;
using pipeline::IsImageExtension;
using pipeline::IsScanExtension;
using pipeline::LoadExtrinsic;
using pipeline::LoadImage;
using pipeline::LoadIntrinsics;
using pipeline::LoadScan;
using pipeline::LoadedIntrinsics;
using pipeline::RenderDepthOverlay;
using pipeline::VisibleDepthRange;
namespace {

namespace fs = std::filesystem;

struct ColorizeArguments {
  std::string scan_path, image_path, intrinsics_path, extrinsic_path, out_path, overlay_path;
};

// What the run found, for the printed summary.
struct ColorizeSummary {
  std::size_t points = 0, in_front = 0;
  mapping::ColorizeResult colors;
  mapping::EdgeAlignment edges;
  DepthRange depth_range;
};

std::string Format(const char* format, double a, double b = 0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

Status CheckArguments(const ColorizeArguments& a) {
  if (!IsScanExtension(a.scan_path))
    return Status::Error("SCAN '" + a.scan_path + "': expected a .pcd or KITTI .bin file");
  if (!IsImageExtension(a.image_path))
    return Status::Error("IMAGE '" + a.image_path + "': expected a .png, .jpg or .jpeg file");
  if (!IsCalibrationExtension(a.intrinsics_path))
    return Status::Error("--intrinsics '" + a.intrinsics_path + "': expected a .json, .yaml or .yml file");
  if (!IsCalibrationExtension(a.extrinsic_path))
    return Status::Error("--extrinsic '" + a.extrinsic_path + "': expected a .json, .yaml or .yml file");
  if (fs::path(a.out_path).extension() != ".ply")
    return Status::Error("--out '" + a.out_path + "': expected a .ply file name");
  if (!a.overlay_path.empty() && fs::path(a.overlay_path).extension() != ".png")
    return Status::Error("--overlay '" + a.overlay_path + "': expected a .png file name");
  if (!a.overlay_path.empty() &&
      fs::path(a.overlay_path).lexically_normal() == fs::path(a.out_path).lexically_normal())
    return Status::Error("--overlay and --out name the same file");
  return Status();
}

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

// Writes the overlay (when asked) and the PLY so that either both appear or neither: the overlay goes to
// a temporary file first (which also proves its folder writable), then the PLY, then the overlay is renamed.
Status WriteOutputs(const ColorizeArguments& a, const ColorizeScan& scan, const ColorizeSummary& summary,
                    const std::optional<Image>& overlay) {
  std::unique_ptr<AtomicFileWriter> overlay_file;
  if (overlay) {
    auto png = EncodePng(*overlay, a.overlay_path);
    if (!png) return png.status();
    overlay_file = std::make_unique<AtomicFileWriter>(a.overlay_path);
    if (Status s = overlay_file->status(); !s.ok()) return s;
    overlay_file->stream().write(reinterpret_cast<const char*>(png->data()), std::streamsize(png->size()));
  }
  if (Status s = exporting::WritePly(a.out_path, ToPointSource(scan, summary.colors)); !s.ok()) return s;
  if (overlay_file) {
    if (Status s = overlay_file->Commit(); !s.ok()) {
      std::error_code ignored;
      fs::remove(a.out_path, ignored);  // neither output rather than half of them
      return s;
    }
  }
  return Status();
}

void PrintSummary(std::ostream& out, const ColorizeArguments& a, const ColorizeSummary& s) {
  const auto row = [&](const std::string& label, const std::string& value) {
    out << "  " << label << std::string(label.size() < 42 ? 42 - label.size() : 1, ' ') << value << "\n";
  };
  const double fraction = double(s.colors.colored) / double(s.colors.in_footprint);
  out << "\n";
  row("points in the scan", std::to_string(s.points));
  row("in front of the camera", std::to_string(s.in_front));
  row("in front of the camera, inside the image", std::to_string(s.colors.in_footprint));
  row("coloured (visible)", std::to_string(s.colors.colored));
  row("coloured fraction", Format("%.2f %%", 100.0 * fraction));
  row("occluded (behind nearer points)", std::to_string(s.colors.occluded));
  if (s.edges.edge_points > 0)
    row("edge-alignment score", Format("%.3f", s.edges.score) + " (" + std::to_string(s.edges.edge_points) +
                                    " depth-edge points of " + std::to_string(s.edges.visible_points) +
                                    " visible)");
  else
    row("edge-alignment score", "n/a (no depth edge among the visible points)");
  out << "    mean image gradient at the scan's depth edges over its mean at all visible points:\n"
      << "    1 = no relation, > 1 = depth edges sit on image edges (higher is better aligned)\n";
  out << "wrote " << a.out_path;
  if (!a.overlay_path.empty())
    out << ", " << a.overlay_path
        << Format(" (depth colours: red %.1f m ... blue %.1f m)", s.depth_range.near_m, s.depth_range.far_m);
  out << "\n";
}

// The intrinsics fitted to the image's size (FitCameraToImage: a centred crop), with a note when the sizes
// differ and a warning when they differ so much that a scaled image is more likely than a cropped one.
Expected<std::shared_ptr<const CameraModel>> CameraForImage(const LoadedIntrinsics& intrinsics,
                                                            const Image& image, const std::string& path) {
  const CameraModel& calibrated = *intrinsics.camera;
  const int w = calibrated.width(), h = calibrated.height();
  if (w == image.width && h == image.height) return intrinsics.camera;
  Eigen::Vector2d shift;
  auto fitted = FitCameraToImage(calibrated, image.width, image.height, &shift);
  if (!fitted) return Status::Error(path + ": " + fitted.error());
  const bool larger = image.width >= w && image.height >= h, smaller = image.width <= w && image.height <= h;
  std::cout << "  note: calibrated for " << w << "x" << h << ", the image is " << image.width << "x"
            << image.height << ": "
            << (larger    ? "the calibrated image taken as its centred crop"
                : smaller ? "taken as a centred crop of the calibrated image"
                          : "taken as a centred crop (centres aligned)")
            << Format(", principal point shifted by (%+.1f, %+.1f) px", shift.x(), shift.y()) << "\n";
  if (std::abs(image.width - w) > w / 4 || std::abs(image.height - h) > h / 4)
    std::cerr
        << "ultrafusion: warning: the image and calibrated sizes differ by more than 25 %: if the image "
           "was scaled rather than cropped, "
        << path << " does not fit it\n";
  return fitted;
}

int RunColorize(const ColorizeArguments& a) {
  if (Status s = CheckArguments(a); !s.ok()) return ReportUsageError(s);
  auto scan = LoadScan(a.scan_path);
  if (!scan) return ReportError(scan.status());
  auto image = LoadImage(a.image_path);
  if (!image) return ReportError(image.status());
  auto intrinsics = LoadIntrinsics(a.intrinsics_path);
  if (!intrinsics) return ReportError(intrinsics.status());
  auto extrinsic = LoadExtrinsic(a.extrinsic_path);
  if (!extrinsic) return ReportError(extrinsic.status());

  std::cout << "ultrafusion colorize\n"
            << "  scan        " << a.scan_path << ": " << scan->points.size() << " points";
  if (scan->dropped_non_finite > 0) std::cout << " (" << scan->dropped_non_finite << " non-finite dropped)";
  std::cout << "\n  image       " << a.image_path << ": " << image->width << "x" << image->height
            << (image->channels == 1 ? " gray" : " RGB") << "\n"
            << "  intrinsics  " << intrinsics->description << "\n"
            << "  extrinsic   " << extrinsic->description << "\n";

  auto fitted = CameraForImage(*intrinsics, *image, a.intrinsics_path);
  if (!fitted) return ReportError(fitted.status());
  const CameraModel& camera = **fitted;

  // The LiDAR frame is the world frame: T_world_cam = T_lidar_cam = T_cam_lidar^-1.
  const SE3 T_world_cam = extrinsic->T_cam_lidar.inverse();
  const SE3 T_cam_world = extrinsic->T_cam_lidar;
  ColorizeSummary summary;
  summary.points = scan->points.size();
  for (const Eigen::Vector3f& p : scan->points)
    if ((T_cam_world * p.cast<double>()).z() > CameraModel::kMinDepth) ++summary.in_front;
  if (summary.in_front == 0)
    return ReportError(Status::Error("no point of " + a.scan_path +
                                     " is in front of the camera: check that " + a.extrinsic_path +
                                     " maps LiDAR points into the camera frame (T_cam_lidar)"));

  const mapping::ColorizerOptions options;
  const mapping::CameraView view{&*image, &camera, T_world_cam, scan->stamp};
  auto colors = mapping::Colorize(scan->points, std::span(&scan->stamp, 1), std::span(&view, 1), options);
  if (!colors) return ReportError(colors.status());
  summary.colors = std::move(*colors);
  if (summary.colors.in_footprint == 0)
    return ReportError(Status::Error("none of the " + std::to_string(summary.in_front) +
                                     " points in front of the camera projects into the image: check the "
                                     "intrinsics and the extrinsic"));

  mapping::EdgeAlignmentOptions edge_options;
  edge_options.visibility = options.visibility;
  const mapping::ProjectedScan projected =
      mapping::ProjectWithOcclusion(scan->points, camera, T_world_cam, options.visibility);
  summary.edges = mapping::EdgeAlignmentScorer(*image, edge_options).Score(projected);

  std::optional<Image> overlay;
  if (!a.overlay_path.empty()) {
    summary.depth_range = VisibleDepthRange(projected);
    overlay = RenderDepthOverlay(*image, projected, summary.depth_range);
  }
  if (Status s = WriteOutputs(a, *scan, summary, overlay); !s.ok()) return ReportError(s);
  PrintSummary(std::cout, a, summary);
  return kExitOk;
}

}  // namespace

Subcommand AddColorizeCommand(CLI::App& app) {
  auto arguments = std::make_shared<ColorizeArguments>();
  CLI::App* colorize = app.add_subcommand(
      "colorize", "Colour one LiDAR scan from one camera image and score the LiDAR-camera calibration");
  colorize->add_option("SCAN", arguments->scan_path, "LiDAR scan: .pcd, or KITTI .bin (float32 x y z i)")
      ->required();
  colorize->add_option("IMAGE", arguments->image_path, "Camera image: .png or .jpg")->required();
  colorize
      ->add_option(
          "--intrinsics", arguments->intrinsics_path,
          "Camera intrinsics: a *-intrinsic JSON, a calibration YAML or a dataset.yaml (first camera)")
      ->required();
  colorize
      ->add_option("--extrinsic", arguments->extrinsic_path,
                   "LiDAR->camera extrinsic: a 4x4 T_cam_lidar JSON, a calibration YAML or a dataset.yaml")
      ->required();
  colorize->add_option("--out", arguments->out_path, "Coloured points (.ply)")->required();
  colorize->add_option("--overlay", arguments->overlay_path, "Image with the projected depth drawn (.png)");
  return {colorize, [arguments] { return RunColorize(*arguments); }};
}

}  // namespace uf::app
