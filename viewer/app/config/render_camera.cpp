#include "viewer/app/config/render_camera.h"

#include "odometry/io/calibration_file.h"

namespace uf::app {

Expected<RenderCamera> LoadRenderCamera(const std::string& path) {
  Expected<std::shared_ptr<const CameraModel>> model = ReadCameraIntrinsicsFile(path);
  if (!model) return model.status();
  const auto* radtan = dynamic_cast<const PinholeRadtan*>(model->get());
  if (radtan == nullptr)
    return Status::Error(path + ": distortion_model: only radial-tangential cameras are rendered");
  if (radtan->width() > 16384 || radtan->height() > 16384)
    return Status::Error(path + ": resolution: must be at most 16384 x 16384 px, got " +
                         std::to_string(radtan->width()) + " x " + std::to_string(radtan->height()));
  RenderCamera camera;
  camera.intrinsics = radtan->intrinsics();
  const PinholeRadtanIntrinsics& k = camera.intrinsics;
  camera.distorted = k.k1 != 0 || k.k2 != 0 || k.p1 != 0 || k.p2 != 0 || k.k3 != 0;
  camera.model = std::static_pointer_cast<const PinholeRadtan>(*model);
  return camera;
}

RenderCamera ResizeRenderCamera(const RenderCamera& camera, int width, int height) {
  RenderCamera resized = camera;
  PinholeIntrinsics& p = resized.intrinsics.pinhole;
  const double sx = static_cast<double>(width) / p.width, sy = static_cast<double>(height) / p.height;
  p.fx *= sx;
  p.fy *= sy;
  p.cx = (p.cx + 0.5) * sx - 0.5;
  p.cy = (p.cy + 0.5) * sy - 0.5;
  p.width = width;
  p.height = height;
  resized.model = std::make_shared<PinholeRadtan>(resized.intrinsics);
  return resized;
}

}  // namespace uf::app
