#include "viewer/pipeline/colorize/colorize_inputs.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "odometry/io/folders/point_cloud_files.h"
#include "odometry/io/image_decode.h"

namespace uf::pipeline {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

bool IsScanExtension(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".pcd" || extension == ".bin";
}

bool IsImageExtension(const std::string& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg";
}

Expected<ColorizeScan> LoadScan(const std::string& path) {
  PointCloudFileInfo info;
  Expected<LidarScan> scan =
      LowerExtension(path) == ".pcd" ? ReadPcdFile(path, &info) : ReadKittiBin(path, &info);
  if (!scan) return scan.status();
  if (scan->points.empty()) return Status::Error(path + ": the scan has no (finite) point");
  ColorizeScan result;
  result.stamp = scan->stamp;
  result.dropped_non_finite = info.dropped_non_finite;
  result.points.reserve(scan->points.size());
  result.intensities.reserve(scan->points.size());
  for (const LidarPoint& p : scan->points) {
    result.points.emplace_back(p.x, p.y, p.z);
    result.intensities.push_back(p.intensity);
  }
  return result;
}

Expected<Image> LoadImage(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path + ": cannot be read");
  EncodedImage encoded;
  encoded.format = LowerExtension(path) == ".png" ? "png" : "jpeg";
  encoded.bytes.assign(std::istreambuf_iterator<char>(in), {});
  if (in.bad()) return Status::Error(path + ": read error");
  if (encoded.bytes.empty()) return Status::Error(path + ": empty file");
  Expected<Image> image = DecodeImage(encoded);
  if (!image) return Status::Error(path + ": cannot be decoded: " + image.error());
  return image;
}

}  // namespace uf::pipeline
