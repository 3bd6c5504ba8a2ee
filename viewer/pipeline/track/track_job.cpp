#include "viewer/pipeline/track/track_job.h"

#include <sstream>

#include "odometry/eval/series_plot.h"
#include "odometry/io/for_each_measurement.h"
#include "odometry/io/image_decode.h"
#include "odometry/io/measurement_stream.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run_files.h"
#include "viewer/pipeline/stages/reliability_files.h"
#include "viewer/pipeline/track/stereo_pairs.h"
#include "viewer/pipeline/track/track_overlay.h"

namespace uf::pipeline {
namespace {

namespace fs = std::filesystem;
using estimator::FrameTrackStats;

constexpr std::size_t kMaxKeptReasons = 5;  // skipped frames whose reason is kept as a warning

Expected<int> FindCamera(const fs::path& dataset, const DatasetDescription& d, const std::string& name) {
  for (std::size_t s = 0; s < d.streams.size(); ++s) {
    const StreamInfo& stream = d.streams[s];
    if (stream.kind != SensorKind::kCamera || (!name.empty() && stream.name != name)) continue;
    if (!stream.camera_model)
      return Status::Error(dataset.string() + ": camera " + stream.name + " has no intrinsics");
    return static_cast<int>(s);
  }
  const std::string wanted = name.empty() ? "a camera stream" : "a camera stream named " + name;
  return Status::Error(dataset.string() + ": track needs " + wanted + "; the dataset has " +
                       (d.streams.empty() ? "no streams" : StreamNames(d)));
}

// The stereo camera's stream: a camera with intrinsics other than the tracked one, both with extrinsics.
Expected<int> FindStereoCamera(const TrackRequest& request, const DatasetDescription& d, int tracked) {
  Expected<int> found = FindCamera(request.dataset, d, request.stereo_camera);
  if (!found) return found;
  const StreamInfo& left = d.streams[static_cast<std::size_t>(tracked)];
  const StreamInfo& right = d.streams[static_cast<std::size_t>(*found)];
  if (*found == tracked)
    return Status::Error("--stereo " + right.name + ": the tracked camera itself; name the other camera");
  if (!left.T_body_sensor || !right.T_body_sensor)
    return Status::Error(request.dataset.string() + ": --stereo needs the extrinsics (T_body_sensor) of " +
                         left.name + " and " + right.name);
  return found;
}

void KeepReason(TrackResult& r, const std::string& reason) {
  if (r.undecodable + r.refused <= static_cast<std::int64_t>(kMaxKeptReasons)) r.warnings.push_back(reason);
}

std::string TracksCsv(const TrackResult& r) {
  std::ostringstream csv;
  csv << "stamp_ns,features,tracked,detected,lost_klt,lost_fb,lost_ransac,lost_spacing,tracked_ratio,"
         "grid_occupancy,epipolar_error_px,parallax_px,mean_intensity,intensity_std,keyframe,time_ms,"
         "degeneracy,stereo_matched,stereo_epipolar_px,warning\n";
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const FrameTrackStats& s = r.frames[i];
    csv << s.stamp << ',' << s.features << ',' << s.tracked << ',' << s.detected << ',' << s.lost_klt << ','
        << s.lost_fb << ',' << s.lost_ransac << ',' << s.lost_spacing << ','
        << PrintfText("%.4f,%.4f,%.4f,%.3f,%.2f,%.2f", s.tracked_ratio, s.grid_occupancy, s.epipolar_error_px,
                      s.parallax_px, s.mean_intensity, s.intensity_std)
        << ',' << (s.keyframe ? 1 : 0) << ',' << PrintfText("%.3f,%.3f,", s.time_ms, r.degeneracy[i].score);
    if (const std::optional<estimator::StereoStats>& pair = r.stereo[i])
      csv << pair->matched << ',' << PrintfText("%.4f", pair->epipolar_px);
    else
      csv << ',';
    csv << ",\"" << s.warning << "\"\n";
  }
  return csv.str();
}

}  // namespace

Expected<TrackResult> RunTrack(const TrackRequest& request, const TrackProgress& progress) {
  Expected<std::unique_ptr<DatasetReader>> reader =
      OpenDataset(request.dataset, request.dataset_config.reader);
  if (!reader) return reader.status();
  Expected<MeasurementStream> stream = MeasurementStream::Create(**reader, request.dataset_config.stream);
  if (!stream) return stream.status();
  Expected<int> camera_stream = FindCamera(request.dataset, stream->description(), request.camera);
  if (!camera_stream) return camera_stream.status();
  const StreamInfo& info = stream->description().streams[static_cast<std::size_t>(*camera_stream)];
  const CameraModel& camera = *info.camera_model;
  Image mask;
  if (!request.mask.empty()) {
    Expected<Image> read = ReadMaskFile(request.mask, camera.width(), camera.height());
    if (!read) return Status::Error("--mask: " + read.error());
    mask = std::move(*read);
  }
  Expected<estimator::FeatureTracker> tracker =
      estimator::FeatureTracker::Create(camera, request.tracker, mask);
  if (!tracker) return Status::Error("track: " + tracker.error());
  int stereo_stream = -1;
  std::optional<StereoPairs> stereo;
  if (!request.stereo_camera.empty()) {
    Expected<int> found = FindStereoCamera(request, stream->description(), *camera_stream);
    if (!found) return found.status();
    stereo_stream = *found;
    const StreamInfo& right = stream->description().streams[static_cast<std::size_t>(stereo_stream)];
    stereo.emplace(camera, *right.camera_model, info.T_body_sensor->inverse() * *right.T_body_sensor);
  }

  TrackResult r;
  r.camera_stream = info.name;
  if (stereo) r.stereo_stream = request.stereo_camera;
  auto keep_stereo = [&](Expected<std::optional<StereoPairResult>> pair) -> Status {
    if (!pair) return pair.status();
    if (*pair) r.stereo[(*pair)->first] = (*pair)->second;
    return Status();
  };
  r.width = camera.width();
  r.height = camera.height();
  r.max_features = request.tracker.max_features;
  std::int64_t seen = 0;
  const Status read = ForEachMeasurement(*stream, [&](Measurement& m) {
    auto* frame = std::get_if<CameraFrame>(&m.data);
    if (!frame || (request.max_frames > 0 && seen >= request.max_frames)) return Status();
    if (stereo && m.stream == stereo_stream) {
      if (Status decoded = DecodeCameraFrame(*frame); !decoded.ok()) {
        ++r.undecodable;
        KeepReason(r, "stereo frame at " + StampText(frame->stamp) + ": " + decoded.message() + ", skipped");
        return Status();
      }
      return keep_stereo(stereo->AddRight(frame->stamp, std::move(frame->image)));
    }
    if (m.stream != *camera_stream) return Status();
    ++seen;
    if (Status decoded = DecodeCameraFrame(*frame); !decoded.ok()) {
      ++r.undecodable;
      KeepReason(r, "frame at " + StampText(frame->stamp) + ": " + decoded.message() + ", skipped");
      return Status();
    }
    Expected<estimator::TrackedFrame> tracked = tracker->Track(frame->stamp, frame->image);
    if (!tracked) {
      ++r.refused;
      KeepReason(r, tracked.error());
      return Status();
    }
    const std::size_t index = r.frames.size();
    r.frames.push_back(tracked->stats);
    const FrameTrackStats& stats = tracked->stats;
    r.degeneracy.push_back(
        estimator::ScoreCameraFrame(stats.tracked, stats.grid_occupancy, stats.epipolar_error_px));
    r.stereo.emplace_back();
    if (stereo) {
      if (Status s = keep_stereo(stereo->AddLeft(index, frame->stamp, frame->image, tracked->features));
          !s.ok())
        return s;
    }
    if (request.overlay_every > 0 && index % static_cast<std::size_t>(request.overlay_every) == 0) {
      const Image overlay = RenderTrackOverlay(frame->image, *tracked, request.tracker.min_track_length);
      Expected<std::vector<std::uint8_t>> png = EncodePng(overlay, "track overlay");
      if (!png) return png.status();
      r.overlays.emplace_back(frame->stamp, std::move(*png));
    }
    if (progress) progress(static_cast<std::int64_t>(r.frames.size()));
    return Status();
  });
  if (!read.ok()) return read;
  for (const ReadWarning& w : (*reader)->warnings())
    r.warnings.push_back(w.stream + ": " + w.what + " (" + std::to_string(w.count) + ")");
  return r;
}

Expected<std::vector<std::string>> WriteTrackOutputs(const fs::path& out, const TrackResult& r) {
  std::error_code error;
  fs::create_directories(out / "plots", error);
  if (error) return Status::Error((out / "plots").string() + ": cannot create: " + error.message());
  std::vector<std::string> written;
  if (Status s = WriteTextFileAtomically(out / "tracks.csv", TracksCsv(r)); !s.ok()) return s;
  written.push_back("tracks.csv");
  if (!r.frames.empty()) {
    std::vector<double> seconds, features, ratio, degeneracy;
    for (std::size_t i = 0; i < r.frames.size(); ++i) {
      seconds.push_back(ToSeconds(r.frames[i].stamp - r.frames.front().stamp));
      features.push_back(r.frames[i].features);
      ratio.push_back(r.frames[i].tracked_ratio);
      degeneracy.push_back(r.degeneracy[i].score);
    }
    const std::string x = "time since the first frame (s)";
    if (Status s = WriteSeriesPlot((out / "plots/track_features.png").string(), seconds, features, "features",
                                   SeriesLevel{static_cast<double>(r.max_features), "wanted"},
                                   "Features per frame, " + r.camera_stream, x, "features");
        !s.ok())
      return s;
    written.push_back("plots/track_features.png");
    if (Status s = WriteSeriesPlot((out / "plots/track_ratio.png").string(), seconds, ratio, "tracked ratio",
                                   std::nullopt,
                                   "Share of the previous frame's features tracked, " + r.camera_stream, x,
                                   "tracked / previous features");
        !s.ok())
      return s;
    written.push_back("plots/track_ratio.png");
    if (Status s = WriteSeriesPlot((out / "plots/track_degeneracy.png").string(), seconds, degeneracy,
                                   "degeneracy D", SeriesLevel{kDegenerateReported, "reported"},
                                   "Camera degeneracy score per frame, " + r.camera_stream, x, "D");
        !s.ok())
      return s;
    written.push_back("plots/track_degeneracy.png");
  }
  for (const auto& [stamp, png] : r.overlays) {
    const std::string name = "plots/tracks_" + std::to_string(stamp) + ".png";
    if (Status s = WriteBinaryFileAtomically(out / name, png); !s.ok()) return s;
    written.push_back(name);
  }
  return written;
}

}  // namespace uf::pipeline
