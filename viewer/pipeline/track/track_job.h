// `ultrafusion track` as a job: the visual front end (odometry/estimator/visual/feature_tracker.h) over the
// frames of one camera stream of a dataset, to judge a camera before a drive or a recording before a run
// (how many features it keeps, how long they live, where the frames are poor). The outputs:
//   tracks.csv                   per frame: stamp_ns, every FrameTrackStats field, the camera's degeneracy
//                                score D (odometry/estimator/schedule/camera_degeneracy.h), with --stereo the
//                                pair's matches and mean epipolar distance (empty without a pair; see
//                                stereo_pairs.h), and the warning last, quoted
//   plots/track_features.png     features per frame over time, with the wanted count as a level
//   plots/track_degeneracy.png   D per frame, with the level 0.5 the summary counts frames at
//   plots/track_ratio.png        share of the previous frame's features tracked into each frame
//   plots/tracks_<stamp_ns>.png  every overlay_every-th frame with its features (see track_overlay.h)
// A frame that fails to decode or that the tracker refuses (stamp not after the previous one, wrong size)
// is counted, its first few reasons kept, and skipped; the run goes on.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "odometry/estimator/schedule/camera_degeneracy.h"
#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/estimator/visual/stereo_matcher.h"
#include "viewer/app/config/dataset_config.h"

namespace uf::pipeline {

struct TrackRequest {
  std::filesystem::path dataset;
  app::DatasetConfig dataset_config;
  std::string camera;           // the camera stream's name; empty: the first camera stream
  std::string stereo_camera;    // a second camera stream to match each frame in (stereo); empty: none
  std::filesystem::path mask;   // optional image of the camera's size: black pixels get no features
  int overlay_every = 20;       // an overlay of every N-th frame; 0: none
  std::int64_t max_frames = 0;  // stop after this many frames; 0: all
  estimator::FeatureTrackerConfig tracker;
};

struct TrackResult {
  std::string camera_stream;
  int width = 0, height = 0;
  int max_features = 0;
  std::vector<estimator::FrameTrackStats> frames;
  std::vector<estimator::CameraDegeneracy> degeneracy;                // one per frame
  std::string stereo_stream;                                          // with a stereo camera
  std::vector<std::optional<estimator::StereoStats>> stereo;          // one per frame; empty: no pair
  std::vector<std::pair<Stamp, std::vector<std::uint8_t>>> overlays;  // PNG bytes per stamp
  std::int64_t undecodable = 0, refused = 0;
  std::vector<std::string> warnings;  // the reader's, and the first reasons of skipped frames
};

// Progress: the frames tracked so far.
using TrackProgress = std::function<void(std::int64_t frames)>;

// Errors: the dataset's (unreadable, damaged), no camera stream (or none of that name; the message lists
// the streams), a camera without intrinsics, a stereo camera that is the tracked one or lacks an extrinsic
// (either camera's T_body_sensor), a stereo frame of the wrong size, a mask that cannot be read or is not the
// camera's size, and an invalid tracker config.
Expected<TrackResult> RunTrack(const TrackRequest& request, const TrackProgress& progress);

// Writes the files listed at the top into `out` (created when missing); returns their names.
Expected<std::vector<std::string>> WriteTrackOutputs(const std::filesystem::path& out,
                                                     const TrackResult& result);

}  // namespace uf::pipeline
