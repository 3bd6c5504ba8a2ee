// Saving and loading a GlobalMap as an OpenVDB file (map.vdb in a run folder), so `ultrafusion export
// RUN_DIR` can write PLY / LAS / glTF later. The file holds one grid per voxel attribute, all with the same
// active voxels and the map's voxel transform (centre of voxel ijk at ijk * voxel_size_m), so VDB tools can
// open it:
//   position_offset (Vec3s, m: representative point - voxel centre), count (Int32), last_stamp (Int64, ns),
//   intensity (float), view_direction_sum (Vec3s), color_mean (Vec3s, sRGB 0..255), color_count (Int32),
//   color_m2 (float, Welford sum of squared colour distances)
// and file metadata: ultrafusion_map_format (int, 2), voxel_size_m, voxel_count, the map's config and
// statistics, and the georeference: has_georef (bool) + georef_latitude_deg, georef_longitude_deg (WGS84)
// and georef_height_m (ellipsoidal), the origin of the east-north-up frame, and georef_T_enu_map (Vec3d
// translation + Vec4d quaternion x y z w: the map frame in that ENU frame).
//
// Saving writes a temporary file beside the destination and renames it into place, so a failure (full
// disk, unwritable folder) never leaves a partial map.vdb. Loading checks every grid and the counts and
// returns an error naming the file and what is wrong (not a VDB file, truncated, a missing grid, ...).
#pragma once

#include <filesystem>
#include <optional>

#include "mapping/global_map.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::mapping {

inline constexpr const char* kMapFileName = "map.vdb";

// Where the map is on the earth: the WGS84 origin of an east-north-up (ENU) frame and the map frame's pose in
// it (p_enu = T_enu_map p_map; identity when the map was built in that ENU frame, otherwise the alignment of
// the trajectory with GNSS that was found after mapping).
struct MapGeoreference {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;  // above the ellipsoid
  SE3 T_enu_map;
};

struct LoadedMap {
  GlobalMap map;
  std::optional<MapGeoreference> georef;
};

// Writes `map` (every voxel, whatever MapView would filter) to `file`, e.g. RUN_DIR / kMapFileName.
Status SaveMap(const GlobalMap& map, const std::optional<MapGeoreference>& georef,
               const std::filesystem::path& file);

// Reads a file written by SaveMap; the map gets the config stored in the file.
Expected<LoadedMap> LoadMap(const std::filesystem::path& file);

}  // namespace uf::mapping
