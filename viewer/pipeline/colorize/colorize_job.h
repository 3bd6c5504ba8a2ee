// `ultrafusion colorize` as a job: one LiDAR scan coloured from one camera image through a calibration, the
// calibration scored by how well the scan's depth edges fall on image edges
// (mapping/colorize_edge_alignment.h), and the outputs: the coloured points as PLY and, when asked, the image
// with the projected depth drawn. The LiDAR frame is the world frame: T_world_cam = T_cam_lidar^-1.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "mapping/colorize_edge_alignment.h"
#include "mapping/colorizer.h"
#include "viewer/pipeline/colorize/colorize_calibration.h"
#include "viewer/pipeline/colorize/colorize_inputs.h"
#include "viewer/pipeline/colorize/colorize_overlay.h"

namespace uf::pipeline {

// The intrinsics fitted to an image's size (FitCameraToImage: a centred crop), with a note when the sizes
// differ and a warning when they differ so much that a scaled image is more likely than a cropped one.
struct FittedCamera {
  std::shared_ptr<const CameraModel> camera;
  std::string note, warning;  // "" when none
};
Expected<FittedCamera> CameraForImage(const LoadedIntrinsics& intrinsics, const Image& image,
                                      const std::string& intrinsics_path);

// What the job found, for the printed summary, and the overlay when asked for.
struct ColorizeSummary {
  std::size_t points = 0, in_front = 0;
  mapping::ColorizeResult colors;
  mapping::EdgeAlignment edges;
  DepthRange depth_range;
  std::optional<Image> overlay;
};

// The files the errors name.
struct ColorizeFileNames {
  std::string scan, extrinsic;
};

// Errors: no point in front of the camera (the extrinsic's direction), none inside the image.
Expected<ColorizeSummary> ColorizeWithImage(const ColorizeScan& scan, const Image& image,
                                            const CameraModel& camera, const SE3& T_cam_lidar, bool overlay,
                                            const ColorizeFileNames& names);

// Writes the overlay (when the summary has one) and the PLY so that either both appear or neither: the
// overlay goes to a temporary file first (which also proves its folder writable), then the PLY, then the
// overlay is renamed.
Status WriteColorizeOutputs(const std::string& out_path, const std::string& overlay_path,
                            const ColorizeScan& scan, const ColorizeSummary& summary);

}  // namespace uf::pipeline
