#include "odometry/eval/relative_pose_error.h"

#include <cassert>

namespace uf {

IndexPairs PairsByFrames(std::size_t count, std::size_t delta) {
  assert(delta > 0);
  IndexPairs pairs;
  for (std::size_t i = 0; i + delta < count; i += delta) pairs.emplace_back(i, i + delta);
  return pairs;
}

IndexPairs PairsByPath(const std::vector<SE3>& poses, double delta) {
  assert(delta > 0);
  std::vector<std::size_t> emitted;
  double path = 0;
  for (std::size_t i = 1; i < poses.size(); ++i) {
    path += (poses[i].translation() - poses[i - 1].translation()).norm();
    if (path >= delta) {
      emitted.push_back(i);
      path = 0;
    }
  }
  IndexPairs pairs;
  for (std::size_t k = 1; k < emitted.size(); ++k) pairs.emplace_back(emitted[k - 1], emitted[k]);
  return pairs;
}

std::vector<double> RelativeTranslationErrors(const std::vector<SE3>& reference,
                                              const std::vector<SE3>& estimate, const IndexPairs& pairs) {
  std::vector<double> errors;
  errors.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    const SE3 reference_motion = reference[i].inverse() * reference[j];
    const SE3 estimate_motion = estimate[i].inverse() * estimate[j];
    errors.push_back((reference_motion.inverse() * estimate_motion).translation().norm());
  }
  return errors;
}

}  // namespace uf
