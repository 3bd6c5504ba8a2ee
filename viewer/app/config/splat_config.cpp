#include "viewer/app/config/splat_config.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>

#include "viewer/app/config/config_sections.h"
#include "viewer/app/config/yaml_fields.h"

namespace uf::app {
namespace {

using yaml::FormatNumber;
using yaml::Number;
using yaml::Setter;
using yaml::Whole;

// [W, H] (two whole numbers).
Setter Size(int& width, int& height) {
  return [&width, &height](const YAML::Node& node) -> std::optional<std::string> {
    int w = 0, h = 0;
    if (!node.IsSequence() || node.size() != 2 || !YAML::convert<int>::decode(node[0], w) ||
        !YAML::convert<int>::decode(node[1], h))
      return "expected [width, height] in px";
    width = w, height = h;
    return std::nullopt;
  };
}

// [r, g, b].
Setter Colour(Eigen::Vector3f& field) {
  return [&field](const YAML::Node& node) -> std::optional<std::string> {
    Eigen::Vector3f value;
    for (int c = 0; c < 3; ++c) {
      float v = 0;
      if (!node.IsSequence() || node.size() != 3 || !YAML::convert<float>::decode(node[c], v) ||
          !std::isfinite(v))
        return "expected [r, g, b] in [0, 1]";
      value[c] = v;
    }
    field = value;
    return std::nullopt;
  };
}

std::map<std::string, Setter> Setters(SplatConfig& c) {
  splat::TrainingOptions& t = c.training;
  return {{"iterations", Whole(t.iterations)},
          {"time_budget_s", Number(c.time_budget_s)},
          {"resolution", Size(c.width, c.height)},
          {"max_width", Whole(c.max_width)},
          {"keyframe_distance_m", Number(c.keyframe_distance_m)},
          {"keyframe_angle_deg", Number(c.keyframe_angle_deg)},
          {"holdout_stride", Whole(c.holdout_stride)},
          {"comparisons", Whole(c.comparisons)},
          {"seed_points", Whole(c.seed_points)},
          {"sky_gaussians", Whole(c.sky_gaussians)},
          {"sh_degree", Whole(t.sh_degree)},
          {"sh_degree_interval", Whole(t.sh_degree_interval)},
          {"lr_position_initial", Number(t.lr_position_initial)},
          {"lr_position_final", Number(t.lr_position_final)},
          {"lr_log_scale", Number(t.lr_log_scale)},
          {"lr_rotation", Number(t.lr_rotation)},
          {"lr_opacity", Number(t.lr_opacity)},
          {"lr_sh_dc", Number(t.lr_sh_dc)},
          {"lr_sh_rest", Number(t.lr_sh_rest)},
          {"adam_beta1", Number(t.adam_beta1)},
          {"adam_beta2", Number(t.adam_beta2)},
          {"adam_epsilon", Number(t.adam_epsilon)},
          {"ssim_weight", Number(t.ssim_weight)},
          {"depth_weight", Number(t.depth_weight)},
          {"densify_from", Whole(t.densify_from)},
          {"densify_until", Whole(t.densify_until)},
          {"densify_interval", Whole(t.densify_interval)},
          {"densify_gradient_threshold", Number(t.densify_gradient_threshold)},
          {"dense_fraction", Number(t.dense_fraction)},
          {"prune_opacity", Number(t.prune_opacity)},
          {"prune_world_fraction", Number(t.prune_world_fraction)},
          {"opacity_reset_interval", Whole(t.opacity_reset_interval)},
          {"max_gaussians", Whole(t.max_gaussians)},
          {"background", Colour(t.render.background)},
          {"seed", Whole(t.seed)}};
}

Status ParseSplatSection(const std::string& file, const YAML::Node& node, SplatConfig& config) {
  if (node.IsNull()) return {};
  return yaml::ParseMap(file, "splat", node, Setters(config));
}

}  // namespace

Status SplatConfig::Validate() const {
  auto error = [](const std::string& field, const std::string& what, double value) {
    return Status::Error(field + ": " + what + ", got " + FormatNumber(value));
  };
  if (!(time_budget_s >= 0)) return error("time_budget_s", "must be >= 0", time_budget_s);
  if ((width > 0) != (height > 0) || width < 0 || height < 0 || width > 16384 || height > 16384)
    return Status::Error("resolution: must be two sizes in [1, 16384] px (or [0, 0]: the default), got [" +
                         std::to_string(width) + ", " + std::to_string(height) + "]");
  if (max_width < 16 || max_width > 16384) return error("max_width", "must be in [16, 16384]", max_width);
  if (!(keyframe_distance_m >= 0)) return error("keyframe_distance_m", "must be >= 0", keyframe_distance_m);
  if (!(keyframe_angle_deg >= 0)) return error("keyframe_angle_deg", "must be >= 0", keyframe_angle_deg);
  if (holdout_stride < 2) return error("holdout_stride", "must be >= 2", holdout_stride);
  if (comparisons < 0) return error("comparisons", "must be >= 0", comparisons);
  if (seed_points == 0) return error("seed_points", "must be > 0", 0);
  if (sky_gaussians < 0) return error("sky_gaussians", "must be >= 0", sky_gaussians);
  if (Status s = training.Validate(); !s.ok()) return s;
  return {};
}

Expected<SplatConfig> LoadSplatConfig(const std::filesystem::path& file, SplatConfig defaults) {
  const std::string name = file.string();
  SplatConfig config = std::move(defaults);
  try {
    const YAML::Node root = YAML::LoadFile(name);
    if (!root.IsNull() && !root.IsMap())
      return Status::Error(name + ": expected a map of sections at the top level");
    if (root.IsMap()) {
      for (const auto& kv : root) {
        const std::string key = kv.first.as<std::string>();
        if (key == "splat") {
          if (Status s = ParseSplatSection(name, kv.second, config); !s.ok()) return s;
        } else if (!IsKnownConfigSection(key)) {
          return Status::Error(name + ": unknown top-level key '" + key + "' (expected " +
                               KnownConfigSectionsList() + ")");
        }
      }
    }
  } catch (const YAML::BadFile&) {
    return Status::Error(name + ": cannot open the configuration file");
  } catch (const YAML::Exception& e) {
    return Status::Error(name + ": " + e.what());
  }
  if (Status s = config.Validate(); !s.ok()) return Status::Error(name + ": splat." + s.message());
  return config;
}

std::string EmitSplatConfig(const SplatConfig& c) {
  const splat::TrainingOptions& t = c.training;
  std::string text = "splat:\n";
  auto line = [&text](const char* key, const std::string& value) {
    text += std::string("  ") + key + ": " + value + "\n";
  };
  line("iterations", std::to_string(t.iterations));
  line("time_budget_s", FormatNumber(c.time_budget_s));
  line("resolution", std::string("[") + std::to_string(c.width) + ", " + std::to_string(c.height) + "]");
  line("max_width", std::to_string(c.max_width));
  line("keyframe_distance_m", FormatNumber(c.keyframe_distance_m));
  line("keyframe_angle_deg", FormatNumber(c.keyframe_angle_deg));
  line("holdout_stride", std::to_string(c.holdout_stride));
  line("comparisons", std::to_string(c.comparisons));
  line("seed_points", std::to_string(c.seed_points));
  line("sky_gaussians", std::to_string(c.sky_gaussians));
  line("sh_degree", std::to_string(t.sh_degree));
  line("sh_degree_interval", std::to_string(t.sh_degree_interval));
  line("lr_position_initial", FormatNumber(t.lr_position_initial));
  line("lr_position_final", FormatNumber(t.lr_position_final));
  line("lr_log_scale", FormatNumber(t.lr_log_scale));
  line("lr_rotation", FormatNumber(t.lr_rotation));
  line("lr_opacity", FormatNumber(t.lr_opacity));
  line("lr_sh_dc", FormatNumber(t.lr_sh_dc));
  line("lr_sh_rest", FormatNumber(t.lr_sh_rest));
  line("adam_beta1", FormatNumber(t.adam_beta1));
  line("adam_beta2", FormatNumber(t.adam_beta2));
  line("adam_epsilon", FormatNumber(t.adam_epsilon));
  line("ssim_weight", FormatNumber(t.ssim_weight));
  line("depth_weight", FormatNumber(t.depth_weight));
  line("densify_from", std::to_string(t.densify_from));
  line("densify_until", std::to_string(t.densify_until));
  line("densify_interval", std::to_string(t.densify_interval));
  line("densify_gradient_threshold", FormatNumber(t.densify_gradient_threshold));
  line("dense_fraction", FormatNumber(t.dense_fraction));
  line("prune_opacity", FormatNumber(t.prune_opacity));
  line("prune_world_fraction", FormatNumber(t.prune_world_fraction));
  line("opacity_reset_interval", std::to_string(t.opacity_reset_interval));
  line("max_gaussians", std::to_string(t.max_gaussians));
  const Eigen::Vector3f& b = t.render.background;
  line("background", std::string("[") + FormatNumber(b.x()) + ", " + FormatNumber(b.y()) + ", " +
                         FormatNumber(b.z()) + "]");
  line("seed", std::to_string(t.seed));
  return text;
}

void DefaultSize(int camera_width, int camera_height, int max_width, int& width, int& height) {
  width = camera_width, height = camera_height;
  while (width > max_width && width >= 2 && height >= 2) width /= 2, height /= 2;
}

}  // namespace uf::app
