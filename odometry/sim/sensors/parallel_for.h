// ParallelFor: runs body(begin, end) over [0, count) split into static contiguous chunks, one std::thread per
// chunk (the calling thread takes the first). Chunk k of n covers [k * count / n, (k + 1) * count / n), so
// each index belongs to exactly one chunk and the split depends only on (count, threads): a body that
// writes only the outputs of its own indices gives identical results for any thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

namespace uf::sim {

// The thread count ParallelFor uses for `threads`: itself when > 0, else the hardware concurrency (>= 1).
inline int ResolveThreadCount(int threads) {
  if (threads > 0) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// Returns when every chunk is done. body must not throw. threads <= 0: hardware concurrency.
inline void ParallelFor(std::size_t count, int threads,
                        const std::function<void(std::size_t begin, std::size_t end)>& body) {
  if (count == 0) return;
  const std::size_t chunks = std::min(count, static_cast<std::size_t>(ResolveThreadCount(threads)));
  const auto chunk_begin = [&](std::size_t k) { return k * count / chunks; };
  std::vector<std::thread> workers;
  workers.reserve(chunks - 1);
  for (std::size_t k = 1; k < chunks; ++k) {
    workers.emplace_back([&body, b = chunk_begin(k), e = chunk_begin(k + 1)] { body(b, e); });
  }
  body(chunk_begin(0), chunk_begin(1));
  for (std::thread& worker : workers) worker.join();
}

}  // namespace uf::sim
