// Writes a map as binary glTF 2.0 (.glb) through tinygltf, for glTF viewers and Cesium:
//  - the points as a POINTS primitive: POSITION (float) and COLOR_0, with an unlit material
//    (KHR_materials_unlit) so viewers show the colours as they are;
//  - optionally a ColoredMesh as a TRIANGLES primitive: POSITION, NORMAL (when every normal is finite and
//    non-zero; normalized), COLOR_0 and uint32 indices, with a matte (metallic 0, roughness 1) material.
// Frames and precision: coordinates are first taken to the output frame (local / enu / utm, see georef.h),
// then made relative to a local origin, the centre of their bounds rounded to 1 m, which is stored as the
// node's translation (a double in the JSON). Positions are therefore floats of at most half the map's extent
// (< 1 mm error for maps up to ~16 km across) however far the map lies from the origin.
// glTF is y-up, our frames are z-up: coordinates are converted, (x, y, z)_gltf = (x, z, -y)_ours, a -90 deg
// rotation about x (x stays east/easting, glTF y is up, glTF z points south). The translation is converted
// the same way; no rotation is stored on the node.
// Colours: glTF's COLOR_0 is linear RGB. By default the map's sRGB bytes are decoded to linear floats
// (IEC 61966-2-1); with linear_float_colors = false they are stored as they are, normalized unsigned bytes
// RGBA (alpha 255), smaller and what many point tools expect, but shown slightly too bright by strict
// viewers. Memory: glb cannot be streamed (tinygltf builds the whole buffer), so the points are capped: when
// the map has more than max_points finite points, every stride-th one is written, stride = ceil(finite /
// max_points), and the stride is recorded in asset.extras.ultrafusion.point_stride (with the frame and
// origin). The mesh is written whole. Non-finite point positions are skipped and counted; a mesh with a
// non-finite vertex, an index out of range, or colours/normals of the wrong length is an error, as is nothing
// to write. The file is written under a temporary name and renamed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "export/export_stats.h"
#include "export/georef.h"
#include "mapping/colored_mesh.h"
#include "mapping/point_source.h"

namespace uf::exporting {

struct GltfOptions {
  OutputCrs crs = OutputCrs::kLocal;
  const Georeference* georef = nullptr;  // needed for kEnu and kUtm; must outlive the call
  std::size_t max_points = 5'000'000;    // > 0; more finite points than this are subsampled
  bool linear_float_colors = true;       // COLOR_0 as linear float RGB; false: sRGB normalized ubyte RGBA
  std::array<std::uint8_t, 3> uncolored_rgb = {128, 128, 128};
};

// `points` and `mesh` may each be null (or empty), not both.
Status WriteGlb(const std::filesystem::path& path, const mapping::PointSource* points,
                const mapping::ColoredMesh* mesh, const GltfOptions& options = {},
                ExportStats* stats = nullptr);

}  // namespace uf::exporting
