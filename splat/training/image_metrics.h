// Image quality metrics for evaluating a trained splat model against real images: PSNR and SSIM on rgb
// images in [0, 1] (row-major, 3 floats per pixel), accumulated in double.
//
// SSIM convention (Wang et al. 2004 as computed by 3DGS' ssim(): conv2d with an 11 x 11 Gaussian window,
// sigma 1.5, padding 5, i.e. ZERO padding and an output of the input's size):
//   mu_x = G * x,  s_x = G * x^2 - mu_x^2,  s_xy = G * (x y) - mu_x mu_y   (G: the normalized window, * the
//   zero-padded correlation; near the border the window covers zeros, as in 3DGS),
//   S = ((2 mu_x mu_y + C1)(2 s_xy + C2)) / ((mu_x^2 + mu_y^2 + C1)(s_x + s_y + C2)),  C1 = 0.01^2, C2 =
//   0.03^2,
// and SSIM = the mean of S over every pixel and channel.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace uf::splat {

inline constexpr int kSsimRadius = 5;  // the window is 2 kSsimRadius + 1 = 11 taps wide
inline constexpr double kSsimSigma = 1.5;
inline constexpr double kSsimC1 = 0.01 * 0.01;
inline constexpr double kSsimC2 = 0.03 * 0.03;

// The 1D window: g_k = exp(-k^2 / (2 sigma^2)) / sum_j exp(-j^2 / (2 sigma^2)), k = -5..5 (index k + 5); the
// 2D window is g_i g_j (it sums to 1).
const std::array<double, 2 * kSsimRadius + 1>& SsimWindow();

// The zero-padded separable blur of one channel (width x height, row-major) with the 2D window:
// out(p) = sum over in-image q of g(q_x - p_x) g(q_y - p_y) in(q). The window is symmetric, so this is both
// the correlation and the convolution.
std::vector<double> BlurWithSsimWindow(const std::vector<double>& image, int width, int height);

// The local statistics SSIM compares, per pixel p of one channel of x and y: the window means mu, variances
// s_x = (G * x^2) - mu_x^2, s_y likewise, and covariance s_xy = (G * xy) - mu_x mu_y.
struct SsimMoments {
  std::vector<double> mu_x, mu_y, s_x, s_y, s_xy;
};
SsimMoments LocalSsimMoments(const std::vector<double>& x, const std::vector<double>& y, int width,
                             int height);

// 10 log10(1 / MSE) in dB with MSE the mean squared difference over all entries (rgb in [0, 1]); +inf for
// identical images. The sizes must match (asserted). With a mask (one per pixel of 3 entries, 0: left out),
// the mean runs over the pixels it keeps.
double Psnr(const std::vector<float>& a, const std::vector<float>& b,
            std::span<const std::uint8_t> mask = {});

// Mean SSIM over pixels and the 3 channels (the convention above); a and b are width x height x 3 (asserted).
double Ssim(const std::vector<float>& a, const std::vector<float>& b, int width, int height);

}  // namespace uf::splat
