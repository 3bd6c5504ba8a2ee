// Ray casting against a Scene with Embree (one BVH over the whole mesh, built once). Queries are const and
// thread-safe; the result of a ray depends only on the ray, so output is deterministic whatever the
// threading.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <span>

#include "odometry/sim/scene/scene.h"
#include "odometry/types/status.h"

namespace uf::sim {

struct Ray {
  Eigen::Vector3f origin;     // world frame, m
  Eigen::Vector3f direction;  // unit vector, world frame
  float max_range = std::numeric_limits<float>::infinity();  // m
};

struct RayHit {
  float distance = std::numeric_limits<float>::infinity();  // m along the ray; infinity: no hit
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();         // unit geometric normal, facing the ray origin
  Material material = Material::kCount;
  std::uint32_t triangle = 0;

  bool hit() const { return distance < std::numeric_limits<float>::infinity(); }
};

class RayCaster {
 public:
  // Builds the BVH. Fails (naming the Embree error, or the first bad vertex or triangle) for an empty mesh,
  // non-finite vertices, out-of-range vertex indices, or a material list of the wrong length.
  static Expected<RayCaster> Create(const Scene& scene);

  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  ~RayCaster();

  // hits[i] for rays[i] (sizes must match). Single-threaded; call from several threads for parallelism
  // (see ParallelFor).
  void Cast(std::span<const Ray> rays, std::span<RayHit> hits) const;
  RayHit Cast(const Ray& ray) const;

 private:
  struct Impl;
  explicit RayCaster(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace uf::sim
