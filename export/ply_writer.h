// Writes map points as a binary PLY file (binary_little_endian 1.0), streaming the PointSource chunk by
// chunk so memory stays bounded whatever the map size. One element `vertex` with, in this order:
//   x y z            float, or double when any |coordinate| of the output frame exceeds 10 km (float keeps
//                    < 1 mm there), when force_double is set, or always for UTM output
//   red green blue   uchar, sRGB; uncoloured points get `uncolored_rgb` (grey) and has_color 0
//   has_color        uchar, 1 when the map coloured the point, 0 otherwise
//   intensity        float, as the sensor reports it
//   nx ny nz         float, unit normal (0 0 0 when unknown)
//   count            uint, observations merged into the point
// Header comments state the frame (and for enu/utm the origin and EPSG code). Points with a non-finite
// position are skipped and counted (ExportStats::points_skipped_nonfinite); the vertex count in the header is
// that of the written points. A map with no finite point is an error. The file is written under a temporary
// name and renamed, so a failed write never leaves a partial file nor replaces an existing one.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>

#include "export/export_stats.h"
#include "export/georef.h"
#include "mapping/point_source.h"

namespace uf::exporting {

struct PlyOptions {
  OutputCrs crs = OutputCrs::kLocal;
  const Georeference* georef = nullptr;  // needed for kEnu and kUtm; must outlive the call
  bool force_double = false;             // double coordinates even near the origin
  std::array<std::uint8_t, 3> uncolored_rgb = {128, 128, 128};
};

Status WritePly(const std::filesystem::path& path, const mapping::PointSource& points,
                const PlyOptions& options = {}, ExportStats* stats = nullptr);

}  // namespace uf::exporting
