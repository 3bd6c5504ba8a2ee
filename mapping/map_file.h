// Saving and loading a GlobalMap (map.vdb + map.voxels in a run folder), so `ultrafusion export RUN_DIR` can
// write PLY / LAS / glTF later.
//
// map.vdb is an OpenVDB file (VDB tools open it) with one Int32 grid, voxel_index (active exactly at the
// occupied voxels, value = the voxel's record number; the map's voxel transform: centre of voxel ijk at
// ijk * voxel_size_m), and the file metadata: ultrafusion_map_format (int, 3), voxel_size_m, voxel_count, the
// map's config and statistics, and the georeference: has_georef (bool) + georef_latitude_deg,
// georef_longitude_deg (WGS84) and georef_height_m (ellipsoidal), the origin of the east-north-up frame, and
// georef_T_enu_map (Vec3d translation + Vec4d quaternion x y z w: the map frame in that ENU frame).
// map.voxels (same name, extension .voxels) holds the attributes: "UFMAPVOX", uint32 version 1, uint32
// record size 72, uint64 count, then per voxel in record order (little-endian): ijk (3 x int32),
// position_offset, view_direction_sum, color_mean (3 x float each: representative point - voxel centre in m,
// sum of unit vectors towards the sensor, mean sRGB 0..255), color_m2 (float, Welford sum), intensity
// (float), count, color_count (uint32), last_stamp (int64 ns).
// Why not one attribute grid each (format 2): the 8^3 leaves of a 5 cm street map are sparsely filled, and
// eight dense leaf buffers cost ~1.3 KB per voxel while saving or loading (12 GB for a 60 s drive); the
// records cost 72 bytes, written and read in chunks.
//
// Saving writes each file under a temporary name and renames it into place (map.voxels first), so a failure
// (full disk, unwritable folder) never leaves a partial file. Loading checks the metadata, the grid, the
// record count against the file size and every record against the grid, and returns an error naming the file
// and what is wrong (not a VDB file, truncated, a missing grid, files of two different maps, ...).
#pragma once

#include <filesystem>
#include <optional>

#include "mapping/global_map.h"
#include "odometry/types/geodetic.h"
#include "odometry/types/se3.h"
#include "odometry/types/status.h"

namespace uf::mapping {

inline constexpr const char* kMapFileName = "map.vdb";

// Where the map is on the earth: the WGS84 origin of an east-north-up (ENU) frame and the map frame's pose in
// it (p_enu = T_enu_map p_map; identity when the map was built in that ENU frame, otherwise the alignment of
// the trajectory with GNSS that was found after mapping).
struct MapGeoreference {
  GeodeticOrigin origin;  // of the ENU frame
  SE3 T_enu_map;
};

struct LoadedMap {
  GlobalMap map;
  std::optional<MapGeoreference> georef;
};

// map.voxels beside a map.vdb.
std::filesystem::path VoxelAttributesFile(const std::filesystem::path& map_file);

// Writes `map` (every voxel, whatever MapView would filter) to `file`, e.g. RUN_DIR / kMapFileName, and its
// attributes to VoxelAttributesFile(file).
Status SaveMap(const GlobalMap& map, const std::optional<MapGeoreference>& georef,
               const std::filesystem::path& file);

// Reads a file written by SaveMap; the map gets the config stored in the file.
Expected<LoadedMap> LoadMap(const std::filesystem::path& file);

}  // namespace uf::mapping
