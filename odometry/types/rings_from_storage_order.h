// Rings (scan lines) of a spinning LiDAR's scan whose file stores none, recovered from the order of its
// points. KITTI's Velodyne files (.bin, and the .pcd copies of them) store the HDL-64E's points ring by
// ring, each ring one turn of azimuth from the same start: along the stored order the azimuth only grows,
// 64 turns in all. Where a scan is stored that way, the turns counted so far are the ring of each point.
// The rings feed the LiDAR map's ring gate (lo.map.min_plane_rings, docs/METHOD.md "Voxel-hash map and PCA
// planes").
#pragma once

#include "odometry/types/measurements.h"

namespace uf {

// Rings a scan must show for them to be derived: fewer turns are no multi-beam ring order, more are no
// LiDAR's (the densest spin 128 lasers).
inline constexpr int kMinDerivedRings = 8;
inline constexpr int kMaxDerivedRings = 512;

// When the scan has no rings and its stored order is ring by ring (the unwrapped azimuth never steps back
// by more than 2 deg and ends within a quarter turn short of, or 0.05 turn past, a whole number of turns
// in [kMinDerivedRings, kMaxDerivedRings]), sets each point's ring to the number of whole turns before it,
// sets has_ring and returns the number of rings; otherwise leaves the scan as it is and returns 0.
int DeriveRingsFromStorageOrder(LidarScan& scan);

}  // namespace uf
