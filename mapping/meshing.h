// A coloured triangle mesh of the map's surfaces (for the glTF export), with OpenVDB.
//
// Method (Hoppe et al., "Surface reconstruction from unorganized points", 1992, on a sparse grid):
//  1. Every point with a normal n (MapView orients normals towards the sensor, i.e. out of the surface)
//     writes, into the voxels x within band_voxels of it, the signed distance to its tangent plane
//     f(x) = n . (x - p), keeping in each voxel the value of the nearest point. Points without a normal
//     are skipped.
//  2. openvdb::tools::volumeToMesh extracts the zero level set f = 0 (quads split into two triangles).
//  3. The band's rim behind open surfaces also changes sign; those faces lie about band_voxels from every
//     point, so triangles with a vertex farther than max_vertex_distance_voxels from every point are
//     dropped.
//  4. Each vertex takes the colour of the nearest coloured point within color_search_voxels (grey 128 if
//     none) and the normal of the nearest point.
// The grid is built around a local origin (the points' bounding-box centre, snapped to the grid), so float
// vertex coordinates stay precise far from the map origin. All points are held in memory while meshing.
#pragma once

#include "mapping/colored_mesh.h"
#include "mapping/point_source.h"
#include "odometry/types/status.h"

namespace uf::mapping {

struct MeshOptions {
  double voxel_size_m = 0.05;               // grid of the signed distance field, > 0 (the map's voxel size)
  int band_voxels = 2;                      // in [1, 8]
  double max_vertex_distance_voxels = 1.5;  // > 0
  double color_search_voxels = 2.0;         // >= 0
  double adaptivity = 0.0;                  // volumeToMesh polygon reduction, in [0, 1]

  // Ok, or an error naming the field and value ("mesh.band_voxels: must be in [1, 8], got 0").
  Status Validate() const;
};

// The mesh of the points' surfaces; empty when no point has a normal. Fails only for bad options.
Expected<ColoredMesh> MeshFromMap(const PointSource& points, const MeshOptions& options = {});

}  // namespace uf::mapping
