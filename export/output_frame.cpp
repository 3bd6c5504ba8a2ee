#include "export/output_frame.h"

#include <cmath>

namespace uf::exporting {

Expected<OutputFrame> OutputFrame::Create(OutputCrs crs, const Georeference* georef,
                                          const std::string& what) {
  if (crs != OutputCrs::kLocal && georef == nullptr)
    return Status::Error(what + ": output frame " + OutputCrsName(crs) +
                         " needs a georeference (none given)");
  return OutputFrame(crs, georef ? std::optional<Georeference>(*georef) : std::nullopt);
}

Eigen::AlignedBox3d OutputFrame::ApplyToBox(const Eigen::AlignedBox3d& map_box) const {
  if (crs_ != OutputCrs::kUtm || map_box.isEmpty()) return map_box;
  Eigen::AlignedBox3d out;
  for (int corner = 0; corner < 8; ++corner)
    out.extend(Apply(map_box.corner(Eigen::AlignedBox3d::CornerType(corner))));
  // Horizontal distance of the farthest corner from the origin, for the earth-curvature drop.
  double d2 = 0;
  for (int corner = 0; corner < 8; ++corner)
    d2 = std::max(d2, map_box.corner(Eigen::AlignedBox3d::CornerType(corner)).head<2>().squaredNorm());
  constexpr double kMinEarthRadius = 6.3e6;  // m, below the smallest WGS84 radius of curvature
  const double bend = 1e-3 * (out.max() - out.min()).norm() + 1.0;
  const Eigen::Vector3d pad(bend, bend, bend + d2 / (2 * kMinEarthRadius));
  return Eigen::AlignedBox3d(out.min() - pad, out.max() + pad);
}

FinitePoints ScanFinitePoints(const mapping::PointSource& points) {
  FinitePoints result;
  points.ForEachChunk([&](std::span<const mapping::MapPoint> chunk) {
    for (const mapping::MapPoint& p : chunk) {
      if (p.position.allFinite()) {
        ++result.finite;
        result.bounds.extend(p.position);
      } else {
        ++result.nonfinite;
      }
    }
    return true;
  });
  return result;
}

Expected<FinitePoints> ScanWritablePoints(const mapping::PointSource& points, const std::string& file) {
  FinitePoints finite = ScanFinitePoints(points);
  if (finite.finite == 0)
    return Status::Error(file + ": nothing to write, the map has no point with a finite position (" +
                         std::to_string(finite.nonfinite) + " non-finite)");
  return finite;
}

Status CheckSecondPass(const std::string& file, const FinitePoints& first, std::size_t written) {
  if (written == first.finite) return {};
  return Status::Error(file + ": the point source changed between passes (" + std::to_string(first.finite) +
                       " then " + std::to_string(written) + " finite points)");
}

}  // namespace uf::exporting
