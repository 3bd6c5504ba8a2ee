#include "splat/gaussian_model.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>

namespace uf::splat {

void GaussianModel::Add(const Eigen::Vector3f& position, const Eigen::Vector3f& log_scale,
                        const Eigen::Quaternionf& rotation, float opacity_logit,
                        const float* sh_coefficients) {
  positions.push_back(position);
  log_scales.push_back(log_scale);
  rotations.push_back(rotation);
  opacity_logits.push_back(opacity_logit);
  sh.insert(sh.end(), sh_coefficients, sh_coefficients + ShStride());
}

void GaussianModel::AddConstantColor(const Eigen::Vector3f& position, const Eigen::Vector3f& log_scale,
                                     const Eigen::Quaternionf& rotation, float opacity_logit,
                                     const Eigen::Vector3f& rgb) {
  std::vector<float> coefficients(ShStride(), 0.0f);
  for (int c = 0; c < 3; ++c) coefficients[c] = (rgb[c] - 0.5f) / kShC0;
  Add(position, log_scale, rotation, opacity_logit, coefficients.data());
}

namespace {

bool AllFinite(const float* values, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(values[i])) return false;
  return true;
}

Status GaussianError(const std::string& context, std::size_t index, const std::string& field, float value,
                     const std::string& what) {
  std::ostringstream message;
  message << context << ": Gaussian " << index << ": " << field << " " << what << ", got " << value;
  return Status::Error(message.str());
}

}  // namespace

Status GaussianModel::Validate(const std::string& context) const {
  if (sh_degree < 0 || sh_degree > kMaxShDegree)
    return Status::Error(context + ": sh_degree must be in [0, 3], got " + std::to_string(sh_degree));
  const std::size_t n = positions.size();
  if (log_scales.size() != n || rotations.size() != n || opacity_logits.size() != n ||
      sh.size() != n * static_cast<std::size_t>(ShStride()))
    return Status::Error(context + ": arrays of different lengths (" + std::to_string(n) + " positions, " +
                         std::to_string(log_scales.size()) + " scales, " + std::to_string(rotations.size()) +
                         " rotations, " + std::to_string(opacity_logits.size()) + " opacities, " +
                         std::to_string(sh.size()) + " SH values for stride " + std::to_string(ShStride()) +
                         ")");
  for (std::size_t i = 0; i < n; ++i) {
    if (!AllFinite(positions[i].data(), 3))
      return GaussianError(context, i, "position", positions[i].norm(), "not finite");
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(log_scales[i][a]) || std::abs(log_scales[i][a]) > 30.0f)
        return GaussianError(context, i, "scale_" + std::to_string(a) + " (log)", log_scales[i][a],
                             "must be finite and in [-30, 30]");
    const float q_norm = rotations[i].coeffs().norm();
    if (!std::isfinite(q_norm) || q_norm < 1e-12f)
      return GaussianError(context, i, "rotation norm", q_norm, "must be finite and non-zero");
    if (!std::isfinite(opacity_logits[i]))
      return GaussianError(context, i, "opacity (logit)", opacity_logits[i], "not finite");
    const float* coefficients = sh.data() + i * ShStride();
    for (int k = 0; k < ShStride(); ++k)
      if (!std::isfinite(coefficients[k]))
        return GaussianError(context, i,
                             "SH coefficient " + std::to_string(k / 3) + " channel " + std::to_string(k % 3),
                             coefficients[k], "not finite");
  }
  return Status();
}

GaussianModel WithShDegree(const GaussianModel& model, int degree) {
  assert(degree >= 0 && degree <= kMaxShDegree);
  GaussianModel out = model;
  out.sh_degree = degree;
  const std::size_t from = model.ShStride(), to = out.ShStride(), kept = std::min(from, to);
  out.sh.assign(model.size() * to, 0.0f);
  for (std::size_t i = 0; i < model.size(); ++i)
    std::copy_n(model.sh.begin() + static_cast<std::ptrdiff_t>(i * from), kept,
                out.sh.begin() + static_cast<std::ptrdiff_t>(i * to));
  return out;
}

}  // namespace uf::splat
