// The overlay `ultrafusion track` writes for one frame: the image (gray made RGB) with each feature as a
// dot coloured by its track length, red for a new corner through yellow to green at min_track_length
// frames and beyond (the length the estimator needs), and a line to where it was in the previous frame.
#pragma once

#include "odometry/estimator/visual/feature_tracker.h"
#include "odometry/types/measurements.h"

namespace uf::pipeline {

Image RenderTrackOverlay(const Image& image, const estimator::TrackedFrame& frame, int min_track_length);

}  // namespace uf::pipeline
