#include "splat/splat_renderer.h"

#include <algorithm>
#include <cmath>

#include "splat/cpu_reference/reference_renderer.h"
#include "splat/vk/backward_pass.h"
#include "splat/vk/buffer.h"
#include "splat/vk/context.h"
#include "splat/vk/forward_pass.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/gaussian_buffers.h"

namespace uf::splat {

struct SplatRenderer::Impl {
  std::unique_ptr<vk::Context> context;
  std::unique_ptr<vk::ForwardPass> forward;
  std::unique_ptr<vk::FrameCommands> frame;
  std::size_t max_per_chunk = 0;
  vk::GaussianBuffers gaussians;
  SplatFrameStats stats;
  // Backward pass (created on first use); rendered: a Render of the uploaded model ran (Backward reads it).
  std::unique_ptr<vk::BackwardPass> backward;
  bool rendered = false;
};

Expected<std::vector<std::string>> ListSplatDevices() {
  Expected<std::vector<vk::DeviceInfo>> devices = vk::ListDevices();
  if (!devices.ok()) return devices.status();
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < devices->size(); ++i)
    lines.push_back(std::to_string(i) + ": " + (*devices)[i].name + " (" + (*devices)[i].type + ")");
  return lines;
}

Expected<std::string> FindSplatDevice(const std::string& device) {
  Expected<std::vector<vk::DeviceInfo>> devices = vk::ListDevices();
  if (!devices.ok()) return devices.status();
  Expected<std::size_t> found = vk::FindDevice(*devices, device);
  if (!found.ok()) return found.status();
  return (*devices)[*found].name;
}

Expected<std::unique_ptr<SplatRenderer>> SplatRenderer::Create(const SplatRendererOptions& options) {
  auto impl = std::make_unique<Impl>();
  Expected<std::unique_ptr<vk::Context>> context = vk::Context::Create({options.device});
  if (!context.ok()) return context.status();
  impl->context = std::move(context.value());
  impl->max_per_chunk = options.max_gaussians_per_chunk;
  Expected<std::unique_ptr<vk::ForwardPass>> forward = vk::ForwardPass::Create(*impl->context);
  if (!forward.ok()) return forward.status();
  impl->forward = std::move(forward.value());
  Expected<std::unique_ptr<vk::FrameCommands>> frame = vk::FrameCommands::Create(*impl->context, 256, 8);
  if (!frame.ok()) return frame.status();
  impl->frame = std::move(frame.value());
  return std::unique_ptr<SplatRenderer>(new SplatRenderer(std::move(impl)));
}

SplatRenderer::SplatRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SplatRenderer::~SplatRenderer() = default;

const std::string& SplatRenderer::device_name() const { return impl_->context->device_name(); }
const SplatFrameStats& SplatRenderer::last_frame_stats() const { return impl_->stats; }

Status SplatRenderer::Upload(const GaussianModel& model) {
  if (Status s = model.Validate(); !s.ok()) return s;
  impl_->rendered = false;
  return vk::UploadGaussians(*impl_->context, model, impl_->max_per_chunk, impl_->gaussians);
}

Expected<RenderedView> SplatRenderer::Render(const SplatCamera& camera, const RenderSettings& settings) {
  if (Status s = camera.Validate(); !s.ok()) return Status::Error("camera: " + s.message());
  if (Status s = ValidateRenderSettings(settings); !s.ok()) return s;
  Impl& m = *impl_;
  const FloatCamera float_camera = MakeFloatCamera(camera);
  m.stats = SplatFrameStats();
  m.stats.gaussians = m.gaussians.count;
  m.rendered = false;
  bool complete = false;
  // A second attempt when the key buffers had to grow.
  for (int attempt = 0; attempt < 2 && !complete; ++attempt) {
    if (Status s = m.forward->Prepare(m.gaussians, float_camera, settings); !s.ok()) return s;
    if (Status s = m.frame->Begin(); !s.ok()) return s;
    m.forward->Record(*m.frame, m.gaussians);
    if (Status s = m.frame->SubmitAndWait(); !s.ok()) return s;
    ++m.stats.submissions;
    complete = m.forward->Finish(&m.stats);
  }
  if (!complete) return Status::Error("splat renderer: key buffers did not grow");
  m.rendered = true;
  const std::vector<double> intervals = m.frame->IntervalsMs();
  for (std::size_t i = 0; i < intervals.size() && i < vk::ForwardPass::kStageCount; ++i)
    m.stats.stage_ms.emplace_back(vk::ForwardPass::kStageNames[i], intervals[i]);
  RenderedView view;
  m.forward->ReadView(&view);
  return view;
}

Expected<GaussianGradients> SplatRenderer::Backward(const ViewGradients& dL_dview) {
  Impl& m = *impl_;
  if (!m.rendered) return Status::Error("splat renderer: Backward needs a Render of the uploaded model");
  const vk::ForwardState forward = m.forward->State(m.gaussians);
  const std::size_t pixels = static_cast<std::size_t>(forward.width) * forward.height;
  auto size_error = [&](const char* field, std::size_t got, std::size_t wanted) {
    return Status::Error("view gradients: " + std::string(field) + " has " + std::to_string(got) +
                         " entries, expected " + std::to_string(wanted) + " (or none)");
  };
  if (dL_dview.rgb.size() != 3 * pixels) return size_error("rgb", dL_dview.rgb.size(), 3 * pixels);
  if (!dL_dview.alpha.empty() && dL_dview.alpha.size() != pixels)
    return size_error("alpha", dL_dview.alpha.size(), pixels);
  if (!dL_dview.depth_sum.empty() && dL_dview.depth_sum.size() != pixels)
    return size_error("depth_sum", dL_dview.depth_sum.size(), pixels);
  if (!m.backward) {
    Expected<std::unique_ptr<vk::BackwardPass>> created = vk::BackwardPass::Create(*m.context);
    if (!created.ok()) return created.status();
    m.backward = std::move(created.value());
  }
  if (Status s = m.backward->Prepare(forward); !s.ok()) return s;
  m.backward->UploadViewGradients(dL_dview, pixels);
  if (Status s = m.frame->Begin(); !s.ok()) return s;
  m.backward->Record(*m.frame, forward);
  if (Status s = m.frame->SubmitAndWait(); !s.ok()) return s;
  const std::vector<double> intervals = m.frame->IntervalsMs();
  std::erase_if(m.stats.stage_ms, [](const auto& stage) { return stage.first.ends_with(" backward"); });
  for (std::size_t i = 0; i < intervals.size() && i < 2; ++i)
    m.stats.stage_ms.emplace_back(i == 0 ? "rasterize backward" : "project backward", intervals[i]);
  GaussianGradients gradients;
  m.backward->Download(forward, &gradients);
  return gradients;
}

}  // namespace uf::splat
