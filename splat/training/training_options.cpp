#include "splat/training/training_options.h"

#include <cmath>
#include <string>

#include "splat/gaussian_model.h"
#include "splat/render_types.h"

namespace uf::splat {

namespace {

std::string Text(double value) {
  std::string text = std::to_string(value);
  while (text.size() > 1 && text.back() == '0' && text[text.size() - 2] != '.') text.pop_back();
  return text;
}

}  // namespace

Status TrainingOptions::Validate() const {
  auto error = [](const char* field, const char* rule, double value) {
    return Status::Error(std::string(field) + ": must be " + rule + ", got " + Text(value));
  };
  if (iterations <= 0) return error("iterations", "> 0", iterations);
  if (sh_degree < 0 || sh_degree > kMaxShDegree) return error("sh_degree", "in [0, 3]", sh_degree);
  if (sh_degree_interval <= 0) return error("sh_degree_interval", "> 0", sh_degree_interval);
  const std::pair<const char*, double> rates[] = {{"lr_position_initial", lr_position_initial},
                                                  {"lr_position_final", lr_position_final},
                                                  {"lr_log_scale", lr_log_scale},
                                                  {"lr_rotation", lr_rotation},
                                                  {"lr_opacity", lr_opacity},
                                                  {"lr_sh_dc", lr_sh_dc},
                                                  {"lr_sh_rest", lr_sh_rest}};
  for (const auto& [field, value] : rates)
    if (!(value >= 0 && value < 10)) return error(field, "in [0, 10)", value);
  if (!(lr_position_final > 0) && lr_position_initial > 0)
    return error("lr_position_final", "> 0 when lr_position_initial is (the decay is log-linear)",
                 lr_position_final);
  if (!(adam_beta1 >= 0 && adam_beta1 < 1)) return error("adam_beta1", "in [0, 1)", adam_beta1);
  if (!(adam_beta2 >= 0 && adam_beta2 < 1)) return error("adam_beta2", "in [0, 1)", adam_beta2);
  if (!(adam_epsilon > 0 && adam_epsilon < 1)) return error("adam_epsilon", "in (0, 1)", adam_epsilon);
  if (!(ssim_weight >= 0 && ssim_weight <= 1)) return error("ssim_weight", "in [0, 1]", ssim_weight);
  if (!(depth_weight >= 0 && depth_weight < 1e6)) return error("depth_weight", "in [0, 1e6)", depth_weight);
  if (densify_from < 0) return error("densify_from", ">= 0", densify_from);
  if (densify_until < densify_from) return error("densify_until", ">= densify_from", densify_until);
  if (densify_interval <= 0) return error("densify_interval", "> 0", densify_interval);
  if (!(densify_gradient_threshold > 0 && std::isfinite(densify_gradient_threshold)))
    return error("densify_gradient_threshold", "> 0", densify_gradient_threshold);
  if (!(dense_fraction > 0 && dense_fraction < 1))
    return error("dense_fraction", "in (0, 1)", dense_fraction);
  if (!(prune_opacity >= 0 && prune_opacity < 1)) return error("prune_opacity", "in [0, 1)", prune_opacity);
  if (!(prune_world_fraction > 0 && std::isfinite(prune_world_fraction)))
    return error("prune_world_fraction", "> 0", prune_world_fraction);
  if (opacity_reset_interval < 0) return error("opacity_reset_interval", ">= 0", opacity_reset_interval);
  if (max_gaussians == 0) return error("max_gaussians", "> 0", 0);
  if (Status s = ValidateRenderSettings(render); !s.ok()) return s;
  return Status();
}

}  // namespace uf::splat
