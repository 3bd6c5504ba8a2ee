// The scan and the image `ultrafusion colorize` reads: a LiDAR scan from a PCD file or a KITTI Velodyne
// .bin (float32 x y z intensity), and a PNG or JPEG image decoded to 8-bit gray or RGB.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "odometry/types/measurements.h"
#include "odometry/types/stamp.h"
#include "odometry/types/status.h"

namespace uf::pipeline {

struct ColorizeScan {
  std::vector<Eigen::Vector3f> points;  // LiDAR frame, m
  std::vector<float> intensities;       // one per point
  Stamp stamp = 0;                      // scan start (0 when the file has no times)
  std::int64_t dropped_non_finite = 0;  // points the reader dropped for a NaN/Inf value
};

// Whether the extension (case-insensitive) is one LoadScan / LoadImage reads: .pcd, .bin / .png, .jpg, .jpeg.
bool IsScanExtension(const std::string& path);
bool IsImageExtension(const std::string& path);

// Errors name the file: unreadable, damaged, no points.
Expected<ColorizeScan> LoadScan(const std::string& path);
// Errors name the file: unreadable, empty, or not decodable.
Expected<Image> LoadImage(const std::string& path);

}  // namespace uf::pipeline
