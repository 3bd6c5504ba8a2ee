#include "viewer/pipeline/track/track_overlay.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace uf::pipeline {

Image RenderTrackOverlay(const Image& image, const estimator::TrackedFrame& frame, int min_track_length) {
  cv::Mat rgb;
  // OpenCV only reads through the wrapper: the const_cast does not lead to a write.
  const cv::Mat source(image.height, image.width, image.channels == 1 ? CV_8UC1 : CV_8UC3,
                       const_cast<std::uint8_t*>(image.pixels.data()));
  if (image.channels == 1)
    cv::cvtColor(source, rgb, cv::COLOR_GRAY2RGB);
  else
    rgb = source.clone();
  const int radius = std::max(2, image.width / 250);
  for (const estimator::TrackedFeature& f : frame.features) {
    // Hue from red (new) to green (min_track_length and longer), full saturation and value, as RGB.
    const double t = std::clamp((f.length - 1.0) / std::max(1, min_track_length - 1), 0.0, 1.0);
    const cv::Scalar color(255 * std::min(1.0, 2 * (1 - t)), 255 * std::min(1.0, 2 * t), 0);
    const cv::Point2d at(f.pixel.x(), f.pixel.y()), before(f.previous_pixel.x(), f.previous_pixel.y());
    if (f.length > 1) cv::line(rgb, before, at, color, 1, cv::LINE_AA);
    cv::circle(rgb, at, radius, color, cv::FILLED, cv::LINE_AA);
  }
  Image out{image.width, image.height, 3, {}};
  out.pixels.assign(rgb.data, rgb.data + rgb.total() * rgb.elemSize());
  return out;
}

}  // namespace uf::pipeline
