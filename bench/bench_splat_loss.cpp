// Speed of the Vulkan photometric loss pass (splat/vk/loss_pass.h; lavapipe when there is no GPU) on a
// random rendered view and target at 320 x 240 by default: device ms of its stages and in all (timestamp
// queries, the pass recorded alone in a frame), medians over the iterations.
//
//   bench_splat_loss [--width W] [--height H] [--iterations I] [--device NAME]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench/splat_bench_scene.h"
#include "splat/vk/buffer.h"
#include "splat/vk/context.h"
#include "splat/vk/frame_commands.h"
#include "splat/vk/loss_pass.h"

namespace {

int Fail(const std::string& message) {
  std::fprintf(stderr, "bench_splat_loss: %s\n", message.c_str());
  return 1;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace uf::splat;
  using uf::Status;
  int width = 320, height = 240, iterations = 20;
  vk::ContextOptions options;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--width"))
      width = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--height"))
      height = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--iterations"))
      iterations = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--device"))
      options.device = argv[i + 1];
    else
      return Fail("usage: [--width W] [--height H] [--iterations I] [--device NAME]");
  }
  auto context = vk::Context::Create(options);
  if (!context.ok()) return Fail(context.error());
  auto frame = vk::FrameCommands::Create(**context, 8, vk::LossPass::kStageCount + 1);
  if (!frame.ok()) return Fail(frame.error());
  auto pass = vk::LossPass::Create(**context);
  if (!pass.ok()) return Fail(pass.error());
  if (Status s = (*pass)->Prepare(width, height); !s.ok()) return Fail(s.message());

  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<float> colour(4 * pixels), depth(2 * pixels);
  TrainingView target;
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 4; ++c) colour[4 * p + c] = uniform(rng);
    depth[2 * p] = depth[2 * p + 1] = 1.0f + 20.0f * uniform(rng);
    for (int c = 0; c < 3; ++c) target.rgb.push_back(uniform(rng));
    target.depth.push_back(uniform(rng) < 0.5f ? 0.0f : depth[2 * p + 1] + uniform(rng) - 0.5f);
  }
  vk::Buffer colour_buffer, depth_buffer, gradients;
  for (auto [buffer, bytes] :
       {std::pair{&colour_buffer, colour.size() * 4}, std::pair{&depth_buffer, depth.size() * 4},
        std::pair{&gradients, pixels * 32}})
    if (Status s = vk::EnsureBuffer(**context, *buffer, bytes, "bench"); !s.ok()) return Fail(s.message());
  colour_buffer.Upload(colour.data(), colour.size() * 4);
  depth_buffer.Upload(depth.data(), depth.size() * 4);
  (*pass)->UploadTarget(target);

  std::vector<std::vector<double>> stage_ms(vk::LossPass::kStageCount);
  std::vector<double> total_ms;
  PhotometricLossValue loss;
  for (int it = 0; it < iterations + 1; ++it) {  // the first frame warms up
    if (Status s = (*frame)->Begin(); !s.ok()) return Fail(s.message());
    (*pass)->Record(**frame, colour_buffer, depth_buffer, gradients, {0.2f, 0.1f});
    if (Status s = (*frame)->SubmitAndWait(); !s.ok()) return Fail(s.message());
    loss = (*pass)->ReadLoss();
    const std::vector<double> intervals = (*frame)->IntervalsMs();
    if (it == 0 || intervals.size() != vk::LossPass::kStageCount) continue;
    double total = 0;
    for (int k = 0; k < vk::LossPass::kStageCount; ++k) {
      stage_ms[k].push_back(intervals[k]);
      total += intervals[k];
    }
    total_ms.push_back(total);
  }
  std::printf("device: %s\n", (*context)->device_name().c_str());
  std::printf("image %d x %d, %d iterations: loss pass %.3f ms (median device time)\n", width, height,
              iterations, Median(total_ms));
  for (int k = 0; k < vk::LossPass::kStageCount; ++k)
    std::printf("  %-20s %.3f ms\n", vk::LossPass::kStageNames[k], Median(stage_ms[k]));
  std::printf("loss total %.6f (l1 %.6f, dssim %.6f, depth %.6f)\n", loss.total, loss.l1, loss.dssim,
              loss.depth);
  std::printf("load average: %s\n", uf::bench::LoadAverage().c_str());
  return 0;
}
