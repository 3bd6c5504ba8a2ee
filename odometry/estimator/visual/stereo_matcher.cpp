#include "odometry/estimator/visual/stereo_matcher.h"

#include <cmath>
#include <opencv2/video/tracking.hpp>

#include "odometry/estimator/visual/epipolar_check.h"
#include "odometry/estimator/visual/gray_frame.h"
#include "odometry/estimator/visual/triangulation.h"
#include "odometry/types/printf_text.h"
#include "odometry/types/so3.h"

namespace uf::estimator {
namespace {

constexpr double kMinContrastDn = 3.0;  // frames with less spread are not normalized (gray_frame.h)

cv::Mat NormalizedGray(const Image& image) {
  cv::Mat gray = GrayOf(image);
  cv::Scalar mean, std_dev;
  cv::meanStdDev(gray, mean, std_dev);
  NormalizeExposure(gray, mean[0], std_dev[0], kMinContrastDn);
  return gray;
}

Status CheckInputs(const Image& left, const Image& right, const CameraModel& left_camera,
                   const CameraModel& right_camera, const SE3& T_left_right, const StereoConfig& c) {
  if (c.klt_window_px < 5 || c.klt_window_px % 2 == 0)
    return Status::Error(
        PrintfText("stereo klt_window_px: must be odd and at least 5, got %.0f", c.klt_window_px));
  if (c.klt_pyramid_levels < 0 || c.klt_pyramid_levels > 8)
    return Status::Error(
        PrintfText("stereo klt_pyramid_levels: must be in [0, 8], got %.0f", c.klt_pyramid_levels));
  if (!(c.max_fb_error_px > 0) || !(c.max_epipolar_px > 0) || !(c.min_depth_m >= 0))
    return Status::Error("stereo: max_fb_error_px and max_epipolar_px must be positive, min_depth_m >= 0");
  if (Status s = left_camera.Validate(); !s.ok()) return Status::Error("stereo left camera: " + s.message());
  if (Status s = right_camera.Validate(); !s.ok())
    return Status::Error("stereo right camera: " + s.message());
  if (!PinholeOf(right_camera))
    return Status::Error("stereo: the right camera model has no pinhole intrinsics");
  if (!T_left_right.translation().allFinite() || !T_left_right.so3().matrix().allFinite())
    return Status::Error("stereo: the extrinsic between the cameras is not finite");
  if (!FitsCamera(left, left_camera) || !FitsCamera(right, right_camera))
    return Status::Error(
        PrintfText("stereo: images %.0f x %.0f and %.0f x %.0f, the cameras %.0f x %.0f and %.0f x %.0f",
                   left.width, left.height, right.width, right.height, left_camera.width(),
                   left_camera.height(), right_camera.width(), right_camera.height()));
  return Status();
}

}  // namespace

Expected<StereoResult> MatchStereo(const std::vector<TrackedFeature>& left_features, const Image& left,
                                   const Image& right, const CameraModel& left_camera,
                                   const CameraModel& right_camera, const SE3& T_left_right,
                                   const StereoConfig& config) {
  if (Status s = CheckInputs(left, right, left_camera, right_camera, T_left_right, config); !s.ok()) return s;
  StereoResult result;
  result.stats.features = static_cast<int>(left_features.size());
  if (left_features.empty()) return result;
  const cv::Mat left_gray = NormalizedGray(left), right_gray = NormalizedGray(right);
  std::vector<cv::Point2f> from, to, back;
  for (const TrackedFeature& f : left_features)
    from.emplace_back(static_cast<float>(f.pixel.x()), static_cast<float>(f.pixel.y()));
  to = from;  // the search starts at the left pixel
  const cv::Size window(config.klt_window_px, config.klt_window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<unsigned char> status, back_status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(left_gray, right_gray, from, to, status, error, window, config.klt_pyramid_levels,
                           criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  back = from;
  cv::calcOpticalFlowPyrLK(right_gray, left_gray, to, back, back_status, error, window,
                           config.klt_pyramid_levels, criteria, cv::OPTFLOW_USE_INITIAL_FLOW);

  const SE3 T_right_left = T_left_right.inverse();
  const Eigen::Matrix3d E = Hat(T_right_left.translation()) * T_right_left.so3().matrix();  // x_r^T E x_l = 0
  const double focal = PinholeOf(right_camera)->fx;
  const std::vector<SE3> cameras = {SE3(), T_left_right};
  double epipolar_sum = 0;
  for (std::size_t i = 0; i < left_features.size(); ++i) {
    const Eigen::Vector2d right_pixel(to[i].x, to[i].y);
    if (!status[i] || !right_camera.InImage(right_pixel)) {
      ++result.stats.lost_klt;
      continue;
    }
    if (!back_status[i] || cv::norm(back[i] - from[i]) > config.max_fb_error_px) {
      ++result.stats.lost_fb;
      continue;
    }
    const std::optional<Eigen::Vector2d> ray = NormalizedRay(right_camera, right_pixel);
    if (!ray) {
      ++result.stats.lost_klt;
      continue;
    }
    const Eigen::Vector2d n_right = *ray, n_left = left_features[i].normalized;
    const double epipolar = focal * SampsonDistance(E, n_left, n_right);
    if (epipolar > config.max_epipolar_px) {
      ++result.stats.lost_epipolar;
      continue;
    }
    const std::vector<Eigen::Vector2d> rays = {n_left, n_right};
    Expected<Triangulation> point = Triangulate(cameras, rays, /*min_parallax_deg=*/0.0, config.min_depth_m);
    if (!point) {
      ++result.stats.lost_depth;
      continue;
    }
    result.matches.push_back({left_features[i].id, right_pixel, n_right, epipolar, point->point_world.z()});
    epipolar_sum += epipolar;
  }
  result.stats.matched = static_cast<int>(result.matches.size());
  result.stats.epipolar_px = result.matches.empty() ? 0.0 : epipolar_sum / result.matches.size();
  return result;
}

}  // namespace uf::estimator
