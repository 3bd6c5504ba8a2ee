// ScenePath: the track of a body trajectory, used to lay a scene out along any trajectory (a default one or
// a recorded one). The trajectory's positions are resampled by arc length in the xy plane every spacing_m;
// each sample keeps the body height z and the heading of the track (atan2 of the xy tangent, rad, from +x
// towards +y). Ground level under the track is z - body_height_m.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "odometry/types/status.h"
#include "odometry/types/trajectory.h"

namespace uf::sim {

class ScenePath {
 public:
  struct Sample {
    Eigen::Vector3d position;  // body position (world, m)
    double heading = 0.0;      // rad, direction of the xy tangent
    double s = 0.0;            // arc length along the xy track from the first sample (m)
  };

  // The nearest point of the xy polyline to a query point.
  struct Nearest {
    double distance = 0.0;  // xy distance (m)
    double s = 0.0;         // arc length of the nearest point
    double z = 0.0;         // body height z of the track there (linear along the segment)
    double lateral = 0.0;   // signed xy offset of the query to the left (+) / right (-) of the track
  };

  // Fails for fewer than 2 poses, non-finite positions, spacing_m <= 0 or body_height_m < 0. A trajectory
  // that does not move (xy length below 1 mm) gives a one-point track heading along the first pose's x axis.
  static Expected<ScenePath> FromTrajectory(const Trajectory& poses, double spacing_m = 1.0,
                                            double body_height_m = 1.8);

  // The same track continued straight (along the end headings, at the end heights) by `meters` before the
  // first and after the last sample; s of the original samples is shifted by `meters`.
  ScenePath Extended(double meters) const;

  const std::vector<Sample>& samples() const { return samples_; }
  double length() const { return samples_.back().s - samples_.front().s; }
  double spacing() const { return spacing_; }
  double body_height() const { return body_height_; }

  // Nearest point of the track (a brute-force-free query on a uniform grid of segments).
  Nearest NearestPoint(double x, double y) const;
  double DistanceXY(const Eigen::Vector3d& p) const { return NearestPoint(p.x(), p.y()).distance; }
  // Ground height under (x, y): z of the nearest track point minus the body height above ground.
  double GroundHeight(double x, double y) const { return NearestPoint(x, y).z - body_height_; }

  // The sample interpolated at arc length s (clamped to the track): position, heading, s.
  Sample At(double s) const;
  // Ground-level points (z - body_height + z_offset) of the track between arc lengths s0 < s1: the
  // interpolated ends and every sample in between.
  std::vector<Eigen::Vector3d> GroundPolyline(double s0, double s1, double z_offset = 0.0) const;
  // Point at arc length s, offset `lateral` m to the left and `up` m above the ground.
  Eigen::Vector3d GroundPoint(double s, double lateral, double up = 0.0) const;

  // Whether a convex polygon (counter-clockwise xy vertices, e.g. an object's footprint) stays at least
  // `clearance` m (xy) away from every segment of the track; false when they intersect.
  bool PolygonClear(const std::vector<Eigen::Vector2d>& polygon, double clearance) const;

  // Axis-aligned xy bounding box of the samples.
  Eigen::Vector2d min_xy() const { return min_xy_; }
  Eigen::Vector2d max_xy() const { return max_xy_; }

 private:
  ScenePath(std::vector<Sample> samples, double spacing, double body_height);
  void BuildIndex();
  std::vector<int> SegmentsNear(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const;

  std::vector<Sample> samples_;
  double spacing_ = 1.0;
  double body_height_ = 0.0;
  Eigen::Vector2d min_xy_, max_xy_;
  // Uniform grid over the xy bounding box: cell -> segments (i, i + 1) whose bounding box touches it.
  double cell_ = 8.0;
  int grid_nx_ = 1, grid_ny_ = 1;
  std::vector<std::vector<int>> grid_;
};

}  // namespace uf::sim
