// Relative pose error as evo computes it (metrics.RPE, filters.filter_pairs_by_index/_by_path, non all-pairs
// mode): pose pairs (i, j) chosen on the estimate, error of a pair = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), with Q the
// reference and P the estimate, of which the translation norm is reported.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "odometry/types/se3.h"

namespace uf {

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

enum class RpeUnit { kFrames, kMetres };

// (0, d), (d, 2d), ...: consecutive multiples of `delta` frames.
IndexPairs PairsByFrames(std::size_t count, std::size_t delta);

// Walks the poses accumulating path length from the first one; each time the accumulated length reaches
// `delta` metres the index is emitted and the count restarts; consecutive emitted indices form the pairs.
IndexPairs PairsByPath(const std::vector<SE3>& poses, double delta);

// Translation norm of (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) for each pair.
std::vector<double> RelativeTranslationErrors(const std::vector<SE3>& reference,
                                              const std::vector<SE3>& estimate, const IndexPairs& pairs);

}  // namespace uf
