// Shared by the writers: the map-frame -> output-frame transform (identity for local/enu, ENU -> UTM for
// utm) and a first pass over a PointSource that counts finite points and bounds them, so headers are exact
// even when some positions are NaN (PointSource::size() and bounds() count those too).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>

#include "export/georef.h"
#include "mapping/point_source.h"

namespace uf::exporting {

class OutputFrame {
 public:
  // Fails for kEnu / kUtm without a georeference; `what` names the file in the message.
  static Expected<OutputFrame> Create(OutputCrs crs, const Georeference* georef, const std::string& what);

  OutputCrs crs() const { return crs_; }
  const Georeference* georef() const { return georef_ ? &*georef_ : nullptr; }

  Eigen::Vector3d Apply(const Eigen::Vector3d& p_map) const {
    return crs_ == OutputCrs::kUtm ? georef_->EnuToUtm(p_map) : p_map;
  }
  // A box that contains the output-frame image of every point of `map_box`: exact for local/enu; for utm the
  // image of the 8 corners, padded for the projection's curvature (the transverse Mercator bends straight
  // lines by < 1e-3 of the extent, and the ellipsoid drops below the ENU plane by d^2 / (2 R), R >= 6.3e6 m,
  // at a horizontal distance d from the origin).
  Eigen::AlignedBox3d ApplyToBox(const Eigen::AlignedBox3d& map_box) const;

 private:
  OutputFrame(OutputCrs crs, std::optional<Georeference> georef) : crs_(crs), georef_(std::move(georef)) {}
  OutputCrs crs_;
  std::optional<Georeference> georef_;
};

struct FinitePoints {
  std::size_t finite = 0, nonfinite = 0;
  Eigen::AlignedBox3d bounds;  // of the finite positions, map frame; empty when finite == 0
};

// One pass over `points` (positions only).
FinitePoints ScanFinitePoints(const mapping::PointSource& points);

// One pass over `points` for a writer of `file`: an error naming the file when no point is finite.
Expected<FinitePoints> ScanWritablePoints(const mapping::PointSource& points, const std::string& file);

// The writers' second pass must see the points the first pass counted: an error naming the file otherwise.
Status CheckSecondPass(const std::string& file, const FinitePoints& first, std::size_t written);

}  // namespace uf::exporting
