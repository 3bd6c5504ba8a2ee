#include "odometry/estimator/visual/gray_frame.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace uf::estimator {

cv::Mat GrayOf(const Image& image) {
  // OpenCV only reads through the wrapper: the const_cast does not lead to a write.
  cv::Mat wrapped(image.height, image.width, image.channels == 1 ? CV_8UC1 : CV_8UC3,
                  const_cast<std::uint8_t*>(image.pixels.data()));
  if (image.channels == 1) return wrapped.clone();
  cv::Mat gray;
  cv::cvtColor(wrapped, gray, cv::COLOR_RGB2GRAY);
  return gray;
}

void NormalizeExposure(cv::Mat& gray, double mean, double std_dev, double min_contrast) {
  constexpr double kExposureMean = 128, kExposureStd = 50, kMaxGain = 8;
  if (std_dev < std::max(min_contrast, 1e-9)) return;
  const double gain = std::clamp(kExposureStd / std_dev, 1 / kMaxGain, kMaxGain);
  gray.convertTo(gray, CV_8U, gain, kExposureMean - gain * mean);
}

void Smooth(cv::Mat& gray, double sigma_px) {
  if (sigma_px > 0) cv::GaussianBlur(gray, gray, cv::Size(0, 0), sigma_px);
}

bool FitsCamera(const Image& image, const CameraModel& camera) {
  return image.width == camera.width() && image.height == camera.height() &&
         (image.channels == 1 || image.channels == 3) &&
         image.pixels.size() == static_cast<std::size_t>(image.width) * image.height * image.channels;
}

std::optional<Eigen::Vector2d> NormalizedRay(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  constexpr double kMinBearingZ = 1e-3;
  const Eigen::Vector3d ray = camera.Unproject(pixel);
  if (!(ray.z() > kMinBearingZ)) return std::nullopt;
  return Eigen::Vector2d(ray.x() / ray.z(), ray.y() / ray.z());
}

}  // namespace uf::estimator
