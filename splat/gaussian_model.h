// GaussianModel: the scene as 3D Gaussians, in the parameterization that 3DGS files and the optimizer use.
//
// Gaussian i has mean mu_i (world frame, m), covariance Sigma_i = R_i S_i S_i^T R_i^T with
// S_i = diag(exp(log_scale_i)) (standard deviations along the local axes, m) and R_i the rotation of the unit
// quaternion q_i (local -> world; stored unnormalized, normalized on use), opacity sigmoid(opacity_logit_i),
// and view-dependent colour from real spherical harmonics up to degree 3 (3DGS convention):
//   colour(d) = max(0, sum_k c_k Y_k(d) + 0.5), d the unit viewing direction from the camera centre to mu_i,
//   Y_0 = 0.28209479177387814 (so f_dc = (colour - 0.5) / Y_0 for a constant colour).
// Colours are display-referred (sRGB-encoded, like the images they are trained on) in [0, 1].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "odometry/types/status.h"

namespace uf::splat {

inline constexpr int kMaxShDegree = 3;
inline constexpr float kShC0 = 0.28209479177387814f;

// Coefficients per colour channel for SH degree d: (d + 1)^2 (1, 4, 9, 16).
constexpr int ShCoefficientsPerChannel(int degree) { return (degree + 1) * (degree + 1); }

struct GaussianModel {
  int sh_degree = 0;                          // 0..3
  std::vector<Eigen::Vector3f> positions;     // mu, world frame, m
  std::vector<Eigen::Vector3f> log_scales;    // ln(sigma) per local axis
  std::vector<Eigen::Quaternionf> rotations;  // local -> world, normalized on use
  std::vector<float> opacity_logits;          // opacity = 1 / (1 + exp(-logit))
  // SH coefficients, coefficient-major per Gaussian: sh[i * ShStride() + k * 3 + c] is coefficient k
  // (0 = DC) of colour channel c (0 R, 1 G, 2 B). (3DGS PLY files store f_rest channel-major; the file
  // readers and writers convert.)
  std::vector<float> sh;

  std::size_t size() const { return positions.size(); }
  int ShStride() const { return 3 * ShCoefficientsPerChannel(sh_degree); }

  // Appends one Gaussian; sh_coefficients has ShStride() entries (coefficient-major as above).
  void Add(const Eigen::Vector3f& position, const Eigen::Vector3f& log_scale,
           const Eigen::Quaternionf& rotation, float opacity_logit, const float* sh_coefficients);
  // Appends one Gaussian of constant colour (rgb in [0, 1]); higher SH coefficients are zero.
  void AddConstantColor(const Eigen::Vector3f& position, const Eigen::Vector3f& log_scale,
                        const Eigen::Quaternionf& rotation, float opacity_logit, const Eigen::Vector3f& rgb);

  // Checks what a renderer relies on: consistent array sizes, SH degree in 0..3, finite values, a
  // non-zero quaternion, log-scales in [-30, 30]. The message names the Gaussian index, field and value,
  // prefixed by `context` (a file name, say).
  Status Validate(const std::string& context = "splats") const;
};

// The model at another SH degree: higher bands are added as zeros (the colour is unchanged) or dropped.
GaussianModel WithShDegree(const GaussianModel& model, int degree);

}  // namespace uf::splat
