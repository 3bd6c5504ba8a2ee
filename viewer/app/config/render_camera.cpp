#include "viewer/app/config/render_camera.h"

#include "odometry/io/calibration_file.h"
#include "splat/views/training_images.h"

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

Expected<std::shared_ptr<const CameraModel>> ResizeCameraModel(const CameraModel& model, int width,
                                                               int height) {
  if (const auto* radtan = dynamic_cast<const PinholeRadtan*>(&model)) {
    PinholeRadtanIntrinsics k = radtan->intrinsics();
    k.pinhole = splat::ScalePinhole(k.pinhole, width, height);
    return std::shared_ptr<const CameraModel>(std::make_shared<PinholeRadtan>(k));
  }
  if (const auto* fisheye = dynamic_cast<const Equidistant*>(&model)) {
    EquidistantIntrinsics k = fisheye->intrinsics();
    k.pinhole = splat::ScalePinhole(k.pinhole, width, height);
    return std::shared_ptr<const CameraModel>(std::make_shared<Equidistant>(k));
  }
  return Status::Error("--width/--height: only pinhole-radtan and equidistant cameras are resized");
}

}  // namespace uf::app
