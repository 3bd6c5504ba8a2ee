#include "odometry/estimator/visual/feature_tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <unordered_map>

#include "odometry/estimator/visual/epipolar_check.h"
#include "odometry/estimator/visual/gray_frame.h"
#include "odometry/types/printf_text.h"

namespace uf::estimator {
namespace {

// Frame quality: a mean below kDarkDn or above kSaturatedDn (of 255) marks a dark or saturated frame.
constexpr double kDarkDn = 15.0;
constexpr double kSaturatedDn = 240.0;
// A keyframe also when fewer than this share of the last keyframe's features are still tracked.
constexpr double kMinKeyframeOverlap = 0.5;

struct LiveTrack {
  long id = 0;
  int length = 1;
  cv::Point2f pixel;
  Eigen::Vector2d normalized;
};

bool InsideAndUnmasked(const cv::Point2f& p, const cv::Mat& mask) {
  const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
  if (x < 0 || y < 0 || x >= mask.cols || y >= mask.rows) return false;
  return mask.at<std::uint8_t>(y, x) != 0;
}

std::string QualityWarning(double mean, double std_dev, double min_contrast) {
  if (mean < kDarkDn) return PrintfText("dark (mean %.1f DN)", mean);
  if (mean > kSaturatedDn) return PrintfText("saturated (mean %.1f DN)", mean);
  if (std_dev < min_contrast) return PrintfText("textureless (intensity std %.2f DN)", std_dev);
  return "";
}

}  // namespace

struct FeatureTracker::Impl {
  std::unique_ptr<CameraModel> camera;
  PinholeIntrinsics pinhole;
  FeatureTrackerConfig config;
  cv::Mat mask;  // 8-bit, non-zero where features may be

  bool has_previous = false;
  Stamp previous_stamp = 0;
  std::vector<cv::Mat> previous_pyramid;
  std::vector<LiveTrack> tracks;
  long next_id = 0;
  std::unordered_map<long, Eigen::Vector2d> keyframe_undistorted;  // the last keyframe's features

  // Undistorted (normalised) coordinates of a pixel; nullopt for a ray at or beyond 90 deg.
  std::optional<Eigen::Vector2d> Normalize(const cv::Point2f& p) const {
    return NormalizedRay(*camera, Eigen::Vector2d(p.x, p.y));
  }
  Eigen::Vector2d Undistorted(const Eigen::Vector2d& normalized) const {
    return {pinhole.fx * normalized.x() + pinhole.cx, pinhole.fy * normalized.y() + pinhole.cy};
  }

  std::vector<LiveTrack> TrackInto(const std::vector<cv::Mat>& pyramid, FrameTrackStats& stats) const;
  void KeepSpaced(std::vector<LiveTrack>& kept, FrameTrackStats& stats) const;
  void Detect(const cv::Mat& gray, std::vector<LiveTrack>& kept, FrameTrackStats& stats);
  void Summarize(const std::vector<LiveTrack>& previous, double dt, TrackedFrame& frame);
};

// Forward, then backward Lucas-Kanade, then the epipolar check on the survivors.
std::vector<LiveTrack> FeatureTracker::Impl::TrackInto(const std::vector<cv::Mat>& pyramid,
                                                       FrameTrackStats& stats) const {
  if (tracks.empty()) return {};
  std::vector<cv::Point2f> from, to, back;
  for (const LiveTrack& t : tracks) from.push_back(t.pixel);
  const cv::Size window(config.klt_window_px, config.klt_window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<unsigned char> status, back_status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(previous_pyramid, pyramid, from, to, status, error, window,
                           config.klt_pyramid_levels, criteria);
  back = from;  // the backward pass starts from where the track was
  cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid, to, back, back_status, error, window,
                           config.klt_pyramid_levels, criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<LiveTrack> kept;
  std::vector<Eigen::Vector2d> undistorted_from, undistorted_to;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    std::optional<Eigen::Vector2d> normalized;
    if (status[i] && InsideAndUnmasked(to[i], mask)) normalized = Normalize(to[i]);
    if (!normalized) {
      ++stats.lost_klt;
      continue;
    }
    if (!back_status[i] || cv::norm(back[i] - from[i]) > config.max_fb_error_px) {
      ++stats.lost_fb;
      continue;
    }
    kept.push_back({tracks[i].id, tracks[i].length + 1, to[i], *normalized});
    undistorted_from.push_back(Undistorted(tracks[i].normalized));
    undistorted_to.push_back(Undistorted(*normalized));
  }
  const EpipolarFit fit =
      FitEpipolar(undistorted_from, undistorted_to, config.ransac_threshold_px, config.ransac_confidence);
  stats.epipolar_error_px = fit.mean_sampson_px;
  std::vector<LiveTrack> inliers;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (fit.inlier[i])
      inliers.push_back(kept[i]);
    else
      ++stats.lost_ransac;
  }
  return inliers;
}

// Longer tracks first; a track closer than min_distance_px to one kept before it is dropped.
void FeatureTracker::Impl::KeepSpaced(std::vector<LiveTrack>& kept, FrameTrackStats& stats) const {
  std::stable_sort(kept.begin(), kept.end(),
                   [](const LiveTrack& a, const LiveTrack& b) { return a.length > b.length; });
  const float d2 = static_cast<float>(config.min_distance_px * config.min_distance_px);
  std::vector<LiveTrack> spaced;
  for (const LiveTrack& t : kept) {
    const bool crowded = std::any_of(spaced.begin(), spaced.end(), [&](const LiveTrack& s) {
      const cv::Point2f d = s.pixel - t.pixel;
      return d.dot(d) < d2;
    });
    if (crowded)
      ++stats.lost_spacing;
    else
      spaced.push_back(t);
  }
  kept = std::move(spaced);
}

void FeatureTracker::Impl::Detect(const cv::Mat& gray, std::vector<LiveTrack>& kept, FrameTrackStats& stats) {
  const int wanted = config.max_features - static_cast<int>(kept.size());
  if (wanted <= 0) return;
  cv::Mat allowed = mask.clone();
  const int radius = static_cast<int>(std::ceil(config.min_distance_px));
  for (const LiveTrack& t : kept) cv::circle(allowed, t.pixel, radius, cv::Scalar(0), cv::FILLED);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(gray, corners, wanted, config.quality_level, config.min_distance_px, allowed);
  for (const cv::Point2f& corner : corners) {
    const std::optional<Eigen::Vector2d> normalized = Normalize(corner);
    if (!normalized) continue;
    kept.push_back({next_id++, 1, corner, *normalized});
    ++stats.detected;
  }
}

void FeatureTracker::Impl::Summarize(const std::vector<LiveTrack>& previous, double dt, TrackedFrame& frame) {
  FrameTrackStats& stats = frame.stats;
  std::unordered_map<long, const LiveTrack*> before;
  for (const LiveTrack& t : previous) before[t.id] = &t;
  const int cells = config.grid_cells;
  std::vector<bool> occupied(static_cast<std::size_t>(cells * cells), false);
  double parallax_sum = 0;
  int common = 0;
  for (const LiveTrack& t : tracks) {
    TrackedFeature f;
    f.id = t.id;
    f.length = t.length;
    f.pixel = {t.pixel.x, t.pixel.y};
    f.previous_pixel = f.pixel;
    f.normalized = t.normalized;
    if (auto it = before.find(t.id); it != before.end() && dt > 0) {
      f.previous_pixel = {it->second->pixel.x, it->second->pixel.y};
      f.velocity = (t.normalized - it->second->normalized) / dt;
    }
    frame.features.push_back(f);
    const int cx = std::clamp(static_cast<int>(t.pixel.x * cells / pinhole.width), 0, cells - 1);
    const int cy = std::clamp(static_cast<int>(t.pixel.y * cells / pinhole.height), 0, cells - 1);
    occupied[static_cast<std::size_t>(cy * cells + cx)] = true;
    if (auto it = keyframe_undistorted.find(t.id); it != keyframe_undistorted.end()) {
      parallax_sum += (Undistorted(t.normalized) - it->second).norm();
      ++common;
    }
  }
  stats.features = static_cast<int>(tracks.size());
  stats.tracked_ratio = previous.empty() ? 0.0 : static_cast<double>(stats.tracked) / previous.size();
  stats.grid_occupancy =
      static_cast<double>(std::count(occupied.begin(), occupied.end(), true)) / occupied.size();
  stats.parallax_px = common > 0 ? parallax_sum / common : 0.0;
  stats.keyframe = keyframe_undistorted.empty() || stats.parallax_px >= config.keyframe_parallax_px ||
                   common < kMinKeyframeOverlap * static_cast<double>(keyframe_undistorted.size());
  if (!stats.keyframe) return;
  keyframe_undistorted.clear();
  for (const LiveTrack& t : tracks) keyframe_undistorted[t.id] = Undistorted(t.normalized);
}

Expected<FeatureTracker> FeatureTracker::Create(const CameraModel& camera, const FeatureTrackerConfig& config,
                                                const Image& mask) {
  if (Status status = ValidateFeatureTrackerConfig(config); !status.ok()) return status;
  if (Status status = camera.Validate(); !status.ok()) return status;
  const std::optional<PinholeIntrinsics> pinhole = PinholeOf(camera);
  if (!pinhole) return Status::Error("feature tracker: the camera model has no pinhole intrinsics");
  auto impl = std::make_unique<Impl>();
  impl->camera = camera.Clone();
  impl->pinhole = *pinhole;
  impl->config = config;
  if (mask.empty()) {
    impl->mask = cv::Mat(camera.height(), camera.width(), CV_8UC1, cv::Scalar(255));
  } else {
    if (mask.width != camera.width() || mask.height != camera.height() || mask.channels != 1)
      return Status::Error(
          PrintfText("feature tracker mask: %.0f x %.0f with %.0f channels, the camera is "
                     "%.0f x %.0f (one channel wanted)",
                     mask.width, mask.height, mask.channels, camera.width(), camera.height()));
    impl->mask = GrayOf(mask);
  }
  return FeatureTracker(std::move(impl));
}

FeatureTracker::FeatureTracker(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
FeatureTracker::FeatureTracker(FeatureTracker&&) noexcept = default;
FeatureTracker& FeatureTracker::operator=(FeatureTracker&&) noexcept = default;
FeatureTracker::~FeatureTracker() = default;

const FeatureTrackerConfig& FeatureTracker::config() const { return impl_->config; }

Expected<TrackedFrame> FeatureTracker::Track(Stamp stamp, const Image& image) {
  Impl& s = *impl_;
  if (s.has_previous && stamp <= s.previous_stamp)
    return Status::Error("camera frame at " + StampText(stamp) + ": not after the previous frame at " +
                         StampText(s.previous_stamp) + ", skipped");
  if (!FitsCamera(image, *s.camera))
    return Status::Error("camera frame at " + StampText(stamp) +
                         PrintfText(": %.0f x %.0f x %.0f pixels, the camera is %.0f x %.0f", image.width,
                                    image.height, image.channels, s.pinhole.width, s.pinhole.height));
  const auto start = std::chrono::steady_clock::now();
  TrackedFrame frame;
  frame.stamp = stamp;
  FrameTrackStats& stats = frame.stats;
  stats.stamp = stamp;
  cv::Mat gray = GrayOf(image);
  cv::Scalar mean, std_dev;
  cv::meanStdDev(gray, mean, std_dev);
  stats.mean_intensity = mean[0];
  stats.intensity_std = std_dev[0];
  stats.warning = QualityWarning(mean[0], std_dev[0], s.config.min_contrast_dn);
  if (s.config.normalize_exposure) NormalizeExposure(gray, mean[0], std_dev[0], s.config.min_contrast_dn);
  Smooth(gray, s.config.smoothing_sigma_px);

  std::vector<cv::Mat> pyramid;
  const cv::Size window(s.config.klt_window_px, s.config.klt_window_px);
  cv::buildOpticalFlowPyramid(gray, pyramid, window, s.config.klt_pyramid_levels);
  std::vector<LiveTrack> kept = s.has_previous ? s.TrackInto(pyramid, stats) : std::vector<LiveTrack>{};
  s.KeepSpaced(kept, stats);
  stats.tracked = static_cast<int>(kept.size());
  s.Detect(gray, kept, stats);

  const double dt = s.has_previous ? ToSeconds(stamp - s.previous_stamp) : 0.0;
  std::vector<LiveTrack> previous = std::move(s.tracks);
  s.tracks = std::move(kept);
  s.Summarize(previous, dt, frame);
  s.previous_pyramid = std::move(pyramid);
  s.previous_stamp = stamp;
  s.has_previous = true;
  stats.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

}  // namespace uf::estimator
