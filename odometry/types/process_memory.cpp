#include "odometry/types/process_memory.h"

#include <malloc.h>

namespace uf {

void KeepFreedMemoryForReuse() {
  constexpr int kMiB = 1 << 20;
  mallopt(M_MMAP_THRESHOLD, 64 * kMiB);
  mallopt(M_TRIM_THRESHOLD, 256 * kMiB);
}

}  // namespace uf
