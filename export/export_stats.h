// What an export wrote: the summary every writer fills in (through an optional out-parameter) so callers can
// report skipped points without the library printing anything.
#pragma once

#include <cstddef>
#include <cstdint>

namespace uf::exporting {

struct ExportStats {
  std::size_t points_written = 0;
  // Points whose position had a NaN or infinite coordinate: skipped, never written.
  std::size_t points_skipped_nonfinite = 0;
  // glb only: every stride-th finite point was written (1 = all), to stay under GltfOptions::max_points.
  std::size_t point_stride = 1;
  std::uint64_t bytes = 0;  // size of the written file
};

}  // namespace uf::exporting
