// Writes map points as LAS 1.4 (ASPRS LAS 1.4 R15), point data record format 7 (36 bytes: x y z, intensity,
// returns, classification, scan angle, user data, point source id, GPS time, RGB), streaming the
// PointSource chunk by chunk so memory stays bounded whatever the map size.
//
// Field mapping (per point):
//   X Y Z            int32 = round((coordinate - offset) / scale), coordinates in the output frame
//   intensity        clamp(round(intensity * intensity_scale), 0, 65535); NaN -> 0
//   return           return number 1 of 1 (a voxel representative, not a pulse)
//   classification   0 (never classified); scan angle 0; scanner channel 0
//   user data        min(observation count, 255)
//   point source id  options.point_source_id
//   GPS time         last_stamp in seconds of the dataset clock (global encoding bit 0 clear)
//   R G B            8-bit sRGB * 257 (so 255 -> 65535); uncoloured points get uncolored_rgb
// Header: scale `scale_m` (coarsened by powers of ten when the extent would overflow int32), offset = the
// minimum of the bounds rounded down to a multiple of 1 m (offset_step_m), min/max of the written
// coordinates, the 64-bit point counts (all points are first returns). The legacy 32-bit counts are 0, as the
// specification requires for formats 6-10 (no legacy compatibility). With crs = kUtm the CRS is written as an
// OGC WKT VLR (user "LASF_Projection", record 2112) and global encoding bit 4 (WKT) is set; local and enu
// output has no CRS record (georef.json says what enu means).
// Non-finite positions are skipped and counted; an empty map is an error; the file is written under a
// temporary name and renamed.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>

#include "export/export_stats.h"
#include "export/georef.h"
#include "mapping/point_source.h"

namespace uf::exporting {

struct LasOptions {
  OutputCrs crs = OutputCrs::kLocal;
  const Georeference* georef = nullptr;  // needed for kEnu and kUtm; must outlive the call
  double scale_m = 0.001;                // coordinate resolution; (0, 1]
  double offset_step_m = 1.0;            // the offset is a multiple of this; > 0
  // LAS intensity is 16-bit, normalized to the sensor's range: 256 maps 8-bit sensors (0..255, the
  // simulator, Velodyne) onto 0..65280; use 65535 for reflectances in [0, 1] (KITTI).
  float intensity_scale = 256.0f;
  std::uint16_t point_source_id = 0;
  std::uint16_t file_source_id = 0;
  std::array<std::uint8_t, 3> uncolored_rgb = {128, 128, 128};
};

// Checks scale_m, offset_step_m and intensity_scale, naming the field and value.
Status ValidateLasOptions(const LasOptions& options);

Status WriteLas(const std::filesystem::path& path, const mapping::PointSource& points,
                const LasOptions& options = {}, ExportStats* stats = nullptr);

}  // namespace uf::exporting
