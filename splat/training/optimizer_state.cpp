#include "splat/training/optimizer_state.h"

#include <algorithm>
#include <cmath>

namespace uf::splat {

bool OptimizerHostState::Consistent() const {
  const std::size_t n = size(), stride = static_cast<std::size_t>(model.ShStride());
  return model.sh.size() == n * stride && m_geometry.size() == n * kGeometryMomentFloats &&
         v_geometry.size() == n * kGeometryMomentFloats && m_sh.size() == n * stride &&
         v_sh.size() == n * stride && gradient_accum.size() == n && gradient_count.size() == n &&
         max_radius.size() == n;
}

void OptimizerHostState::ResizeToModel() {
  const std::size_t n = size(), stride = static_cast<std::size_t>(model.ShStride());
  m_geometry.resize(n * kGeometryMomentFloats, 0.0f);
  v_geometry.resize(n * kGeometryMomentFloats, 0.0f);
  m_sh.resize(n * stride, 0.0f);
  v_sh.resize(n * stride, 0.0f);
  gradient_accum.resize(n, 0.0f);
  gradient_count.resize(n, 0);
  max_radius.resize(n, 0.0f);
}

void OptimizerHostState::ResetStatistics() {
  std::fill(gradient_accum.begin(), gradient_accum.end(), 0.0f);
  std::fill(gradient_count.begin(), gradient_count.end(), 0u);
  std::fill(max_radius.begin(), max_radius.end(), 0.0f);
}

float AdamBiasCorrection(float beta, int step) {
  return static_cast<float>(1.0 - std::pow(static_cast<double>(beta), static_cast<double>(step)));
}

}  // namespace uf::splat
