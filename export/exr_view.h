// Rendered splat views as OpenEXR images (OpenEXR 3.1, scan lines, ZIP compression, lossless), and a small
// reader used by the tests and the render command's tests.
//
// Channels written (data window = display window = the whole image, pixel (x, y) at row y, column x):
//   R G B     colour, half (default) or float. EXR is scene-linear by convention, while RenderedView holds
//             display-referred values (sRGB-encoded, what the splats were trained on), so each value v is
//             decoded with the sRGB EOTF (IEC 61966-2-1):
//               linear = v / 12.92                        for v <= 0.04045 (also for negative v)
//               linear = ((v + 0.055) / 1.055)^2.4        otherwise (also for v > 1, which blending allows)
//             The values are the rendered ones, composited over RenderSettings::background; with the
//             default black background they are the premultiplied (associated-alpha) colour EXR expects.
//   A         alpha = 1 - final transmittance, same pixel type as RGB, not converted.
//   Z         float: the median depth of RenderedView::depth (t_z of the Gaussian at which accumulated alpha
//             reaches 0.5), metres along the camera's optical axis; the standard EXR depth channel name,
//             so compositing tools pick it up as depth.
//   depth.expected  float: the alpha-weighted mean depth RenderedView::expected_depth, metres. A second
//             depth has no standard EXR name; putting it in its own layer ("depth") keeps it out of the
//             default RGBAZ layer that viewers show, and the name says what it is.
// Background or no-depth pixels keep +inf in Z and depth.expected (RenderedView::kNoDepth), which EXR floats
// represent exactly; consumers test isinf(). Half RGB: values above 65504 become inf (never for colours in
// [0, 1]); the half rounding error is at most 2^-11 relative (about 5e-4).
// Written through AtomicFileWriter (temporary name, then rename): a failed write leaves no file behind and
// never replaces a good one. Library code: errors come back as Status, OpenEXR exceptions are caught.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "odometry/types/status.h"
#include "splat/render_types.h"

namespace uf::exporting {

// kUint only appears when reading foreign files; WriteViewExr takes kHalf or kFloat.
enum class ExrPixelType { kHalf, kFloat, kUint };

inline constexpr const char* kExrExpectedDepthChannel = "depth.expected";

// sRGB EOTF (display-referred value -> linear), as applied to R, G, B above.
float SrgbToLinear(float v);

Status WriteViewExr(const splat::RenderedView& view, const std::string& path,
                    ExrPixelType rgba_type = ExrPixelType::kHalf);

// An EXR image read back: every channel as floats over the data window (row-major, width x height).
struct ExrImage {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;
  std::map<std::string, ExrPixelType> types;  // the stored pixel type of each channel
};

// Reads any scan-line or tiled single-part EXR with unsubsampled channels (at most 2^28 values in all).
Expected<ExrImage> ReadExr(const std::string& path);

}  // namespace uf::exporting
