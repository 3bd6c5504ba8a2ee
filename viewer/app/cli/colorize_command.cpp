#include "viewer/app/cli/colorize_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "viewer/app/cli/exit_codes.h"
#include "viewer/pipeline/colorize/colorize_calibration.h"
#include "viewer/pipeline/colorize/colorize_inputs.h"
#include "viewer/pipeline/colorize/colorize_job.h"

namespace uf::app {

using pipeline::IsCalibrationExtension;
using pipeline::IsImageExtension;
using pipeline::IsScanExtension;
using pipeline::LoadExtrinsic;
using pipeline::LoadImage;
using pipeline::LoadIntrinsics;
using pipeline::LoadScan;
namespace {

namespace fs = std::filesystem;

struct ColorizeArguments {
  std::string scan_path, image_path, intrinsics_path, extrinsic_path, out_path, overlay_path;
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

void PrintSummary(std::ostream& out, const ColorizeArguments& a, const pipeline::ColorizeSummary& s) {
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

  auto fitted = pipeline::CameraForImage(*intrinsics, *image, a.intrinsics_path);
  if (!fitted) return ReportError(fitted.status());
  if (!fitted->note.empty()) std::cout << "  note: " << fitted->note << "\n";
  if (!fitted->warning.empty()) std::cerr << "ultrafusion: warning: " << fitted->warning << "\n";
  auto summary = pipeline::ColorizeWithImage(*scan, *image, *fitted->camera, extrinsic->T_cam_lidar,
                                             !a.overlay_path.empty(), {a.scan_path, a.extrinsic_path});
  if (!summary) return ReportError(summary.status());
  if (Status s = pipeline::WriteColorizeOutputs(a.out_path, a.overlay_path, *scan, *summary); !s.ok())
    return ReportError(s);
  PrintSummary(std::cout, a, *summary);
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
