#include "splat/views/camera_view_renderer.h"

#include "splat/views/training_images.h"

namespace uf::splat {

Expected<CameraViewRenderer> CameraViewRenderer::Create(const CameraModel& model) {
  const std::optional<PinholeIntrinsics> pinhole = PinholeOf(model);
  if (!pinhole) return Status::Error("unsupported camera model (pinhole-radtan and equidistant are)");
  CameraViewRenderer renderer(*pinhole);
  if (IsDistorted(model)) renderer.resampler_.emplace(model, *pinhole);
  return renderer;
}

Expected<RenderedView> CameraViewRenderer::Render(const SE3& T_world_camera, const RenderSettings& settings,
                                                  const PinholeRender& render) const {
  SplatCamera camera;
  if (resampler_) {
    camera = resampler_->Pinhole(T_world_camera);
  } else {
    camera.pinhole = pinhole_;
    camera.T_world_camera = T_world_camera;
  }
  Expected<RenderedView> view = render(camera, settings);
  if (!view) return view;
  if (resampler_) return resampler_->Resample(*view, settings.background);
  return view;
}

}  // namespace uf::splat
