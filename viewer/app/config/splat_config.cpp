// The `splat:` section: its schema (every key once, with its unit and meaning) and its checks.
#include "viewer/app/config/splat_config.h"

#include <cmath>

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::KeyPath;
using config::Schema;
using config::ValueText;
using splat::TrainingOptions;

// resolution: [W, H], two whole numbers.
Status ReadResolution(const KeyPath& at, const YAML::Node& node, SplatConfig& config) {
  int size[2] = {0, 0};
  if (!node.IsSequence() || node.size() != 2)
    return at.Error(node, "expected [width, height] in px, got '" + config::Text(node) + "'");
  for (int i = 0; i < 2; ++i)
    if (Status s = config::Read(at[i], node[i], size[i]); !s.ok()) return s;
  config.width = size[0], config.height = size[1];
  return {};
}

ValueText WriteResolution(const SplatConfig& config) {
  return config::Cat({"[", std::to_string(config.width), ", ", std::to_string(config.height), "]"});
}

Schema<SplatConfig> MakeSplatSchema() {
  Schema<TrainingOptions> head;  // the optimizer's steps, ahead of what the command decides
  head.Key("iterations", &TrainingOptions::iterations, "steps",
           "optimizer steps; each takes one training image (a shuffled pass at a time)");

  Schema<TrainingOptions> t;
  t.Key("sh_degree", &TrainingOptions::sh_degree, "",
        "final spherical-harmonics degree, 0..3; the active degree starts at 0");
  t.Key("sh_degree_interval", &TrainingOptions::sh_degree_interval, "steps",
        "the active degree rises by one every this many iterations");
  t.Key("lr_position_initial", &TrainingOptions::lr_position_initial, "x scene extent",
        "Adam learning rate of the positions, times the scene extent (radius of the training cameras), "
        "decaying log-linearly to lr_position_final");
  t.Key("lr_position_final", &TrainingOptions::lr_position_final, "x scene extent",
        "the positions' learning rate at the last iteration");
  t.Key("lr_log_scale", &TrainingOptions::lr_log_scale, "", "learning rate of the log scales");
  t.Key("lr_rotation", &TrainingOptions::lr_rotation, "", "learning rate of the rotations");
  t.Key("lr_opacity", &TrainingOptions::lr_opacity, "", "learning rate of the opacities");
  t.Key("lr_sh_dc", &TrainingOptions::lr_sh_dc, "", "learning rate of the base colours (SH degree 0)");
  t.Key("lr_sh_rest", &TrainingOptions::lr_sh_rest, "", "learning rate of the higher SH coefficients");
  t.Key("adam_beta1", &TrainingOptions::adam_beta1, "", "Adam's first-moment decay");
  t.Key("adam_beta2", &TrainingOptions::adam_beta2, "", "Adam's second-moment decay");
  t.Key("adam_epsilon", &TrainingOptions::adam_epsilon, "", "Adam's epsilon");
  t.Key("ssim_weight", &TrainingOptions::ssim_weight, "", "loss = (1 - w) L1 + w (1 - SSIM)");
  t.Key("depth_weight", &TrainingOptions::depth_weight, "",
        "+ this times the mean relative error |expected depth - LiDAR depth| / LiDAR depth (0: no depth "
        "loss; > 0 projects the map points into every image as its LiDAR depth, which keeps Gaussians from "
        "floating in front of what the LiDAR measured)");
  t.Key("densify_from", &TrainingOptions::densify_from, "steps",
        "densification (clone / split by screen-space gradient, then pruning) every densify_interval "
        "iterations in [densify_from, densify_until)");
  t.Key("densify_until", &TrainingOptions::densify_until, "steps", "the end of densification");
  t.Key("densify_interval", &TrainingOptions::densify_interval, "steps", "iterations between densifications");
  t.Key("densify_gradient_threshold", &TrainingOptions::densify_gradient_threshold, "NDC",
        "mean screen-space gradient above which a Gaussian densifies");
  t.Key("dense_fraction", &TrainingOptions::dense_fraction, "x scene extent",
        "cloned when its largest scale is at most this, else split");
  t.Key("prune_opacity", &TrainingOptions::prune_opacity, "", "pruned below this opacity");
  t.Key("prune_world_fraction", &TrainingOptions::prune_world_fraction, "x scene extent",
        "... or when larger than this");
  t.Key("opacity_reset_interval", &TrainingOptions::opacity_reset_interval, "steps",
        "opacities clamped to 0.01 every this many iterations (0: never)");
  t.Key("max_gaussians", &TrainingOptions::max_gaussians, "Gaussians",
        "densification stops growing the model here");
  t.Key(
      "background", [](auto& o) -> auto& { return o.render.background; }, "rgb in [0, 1]",
      "behind the splats in the training renders");
  t.Key("seed", &TrainingOptions::seed, "", "the shuffling of the images (same seed, same order)");

  using C = SplatConfig;
  Schema<C> s("splat");
  s.Nest("", &C::training, head);
  s.Key("time_budget_s", &C::time_budget_s, "s",
        "stop training after this long, whatever the iteration (0: no limit)");
  s.Custom("resolution", ReadResolution, WriteResolution, "px",
           "training images W x H; [0, 0]: the camera's size halved until the width is <= max_width "
           "(640 x 480 -> 320 x 240); the intrinsics follow the resize");
  s.Key("max_width", &C::max_width, "px", "the bound of the default resolution");
  s.Key("coarse_to_fine_interval", &C::coarse_to_fine_interval, "steps",
        "a resolution wider than max_width is trained first at its size halved until the width is <= "
        "max_width, then doubled every this many iterations up to the resolution (the early steps, which "
        "place the model, cost a fraction); 0: the resolution throughout");
  s.Key("keyframe_distance_m", &C::keyframe_distance_m, "m",
        "an image is used when the camera moved this far since the last one used");
  s.Key("keyframe_angle_deg", &C::keyframe_angle_deg, "deg", "... or turned this much");
  s.Key("holdout_stride", &C::holdout_stride, "images",
        "every n-th image used (index % n == n / 2, never the last: each lies between training images) is "
        "held out: never trained on, PSNR / SSIM reported on them; >= 2");
  s.Key("comparisons", &C::comparisons, "views",
        "held-out views written to comparisons/ (render, real, side by side, EXR)");
  s.Key("seed_points", &C::seed_points, "points",
        "at most this many map points seed Gaussians (more are thinned evenly)");
  s.Key(
      "feature_seed_corners", &C::feature_seed_corners, "corners",
      "per training image, tracked across them and triangulated with the run's poses into seeds where "
      "the map has no point (what the LiDAR did not reach; viewer/pipeline/splat/feature_seeds.h); 0: none");
  s.Key("sky_gaussians", &C::sky_gaussians, "Gaussians",
        "on a sphere beyond the map (radius: 1.2 x the 95th percentile distance of the map from the cameras) "
        "that learn the sky and far background (0: none)");
  s.Key("mask_image", &C::mask_image, "path",
        "an image of the camera's size (PNG) that is black where the camera sees nothing to learn (the car's "
        "own hood): those pixels are not trained on nor scored; pixels an undistorted view cannot fill are "
        "masked without it");
  s.Key("exposure_compensation", &C::exposure_compensation, "",
        "fit each training image's gain and bias per channel with the splats (automatic exposure and white "
        "balance); held-out images take theirs interpolated in time between the training images around them");
  s.Key("exposure_from", &C::exposure_from, "steps",
        "the exposures are fitted from this iteration on (the splats first learn the average appearance)");
  s.Key("exposure_prior", &C::exposure_prior, "",
        "weight per pixel of the pull of each exposure towards gain 1, bias 0");
  s.Nest("", &C::training, t);
  return s;
}

}  // namespace

Status SplatConfig::Validate() const {
  auto error = [](const std::string& field, const std::string& what, double value) {
    return Status::Error(field + ": " + what + ", got " + config::FormatNumber(value));
  };
  if (!(time_budget_s >= 0)) return error("time_budget_s", "must be >= 0", time_budget_s);
  if ((width > 0) != (height > 0) || width < 0 || height < 0 || width > 16384 || height > 16384)
    return Status::Error("resolution: must be two sizes in [1, 16384] px (or [0, 0]: the default), got [" +
                         std::to_string(width) + ", " + std::to_string(height) + "]");
  if (max_width < 16 || max_width > 16384) return error("max_width", "must be in [16, 16384]", max_width);
  if (coarse_to_fine_interval < 0)
    return error("coarse_to_fine_interval", "must be >= 0", coarse_to_fine_interval);
  if (!(keyframe_distance_m >= 0)) return error("keyframe_distance_m", "must be >= 0", keyframe_distance_m);
  if (!(keyframe_angle_deg >= 0)) return error("keyframe_angle_deg", "must be >= 0", keyframe_angle_deg);
  if (holdout_stride < 2) return error("holdout_stride", "must be >= 2", holdout_stride);
  if (comparisons < 0) return error("comparisons", "must be >= 0", comparisons);
  if (seed_points == 0) return error("seed_points", "must be > 0", 0);
  if (feature_seed_corners < 0 || feature_seed_corners > 100000)
    return error("feature_seed_corners", "must be in [0, 100000]", feature_seed_corners);
  if (sky_gaussians < 0) return error("sky_gaussians", "must be >= 0", sky_gaussians);
  if (exposure_from < 0) return error("exposure_from", "must be >= 0", exposure_from);
  if (!(exposure_prior >= 0 && std::isfinite(exposure_prior)))
    return error("exposure_prior", "must be finite and >= 0", exposure_prior);
  if (Status s = training.Validate(); !s.ok()) return s;
  return {};
}

std::string EmitSplatConfig(const SplatConfig& config) {
  return config::EmitSection(config::SplatSchema(), config);
}

namespace {

// How many times DefaultSize halves width x height.
int HalvingsToFit(int width, int height, int max_width) {
  int halvings = 0;
  for (; width > max_width && width >= 2 && height >= 2; width /= 2, height /= 2) ++halvings;
  return halvings;
}

}  // namespace

void DefaultSize(int camera_width, int camera_height, int max_width, int& width, int& height) {
  width = camera_width, height = camera_height;
  for (int n = HalvingsToFit(camera_width, camera_height, max_width); n > 0; --n) width /= 2, height /= 2;
}

void CoarseToFineSize(const SplatConfig& config, int width, int height, int iteration, int& coarse_width,
                      int& coarse_height) {
  coarse_width = width, coarse_height = height;
  if (config.coarse_to_fine_interval <= 0) return;
  const int levels = HalvingsToFit(width, height, config.max_width);
  for (int n = levels - iteration / config.coarse_to_fine_interval; n > 0; --n)
    coarse_width /= 2, coarse_height /= 2;
}

namespace config {

const Schema<SplatConfig>& SplatSchema() { return BuiltOnce<MakeSplatSchema>(); }

}  // namespace config
}  // namespace uf::app
