#include "export/exr_view.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <half.h>

#include <cassert>
#include <cmath>
#include <cstdint>
#include <exception>

#include "odometry/io/atomic_file.h"

namespace uf::exporting {
namespace {

constexpr std::int64_t kMaxExrPixels = std::int64_t{1} << 28;

Imf::PixelType ToImf(ExrPixelType type) {
  assert(type != ExrPixelType::kUint && "WriteViewExr writes half or float RGBA");
  return type == ExrPixelType::kHalf ? Imf::HALF : Imf::FLOAT;
}

ExrPixelType FromImf(Imf::PixelType type) {
  switch (type) {
    case Imf::HALF:
      return ExrPixelType::kHalf;
    case Imf::UINT:
      return ExrPixelType::kUint;
    default:
      return ExrPixelType::kFloat;
  }
}

// One channel's pixels in the stored type: halves or floats.
struct Plane {
  std::vector<half> halves;
  std::vector<float> floats;
  const char* data() const {
    return halves.empty() ? reinterpret_cast<const char*>(floats.data())
                          : reinterpret_cast<const char*>(halves.data());
  }
};

Plane MakePlane(std::size_t n, ExrPixelType type, auto&& value) {
  Plane plane;
  if (type == ExrPixelType::kHalf) {
    plane.halves.resize(n);
    for (std::size_t i = 0; i < n; ++i) plane.halves[i] = half(value(i));
  } else {
    plane.floats.resize(n);
    for (std::size_t i = 0; i < n; ++i) plane.floats[i] = value(i);
  }
  return plane;
}

Status CheckView(const splat::RenderedView& view, const std::string& path) {
  if (view.width <= 0 || view.height <= 0 || std::int64_t{view.width} * view.height > kMaxExrPixels)
    return Status::Error(path + ": view size " + std::to_string(view.width) + " x " +
                         std::to_string(view.height) + " is empty or too large");
  const std::size_t n = std::size_t(view.width) * view.height;
  if (view.rgb.size() != 3 * n || view.alpha.size() != n || view.depth.size() != n ||
      view.expected_depth.size() != n)
    return Status::Error(path + ": view arrays do not match its size " + std::to_string(view.width) + " x " +
                         std::to_string(view.height) + " (rgb " + std::to_string(view.rgb.size()) +
                         ", alpha " + std::to_string(view.alpha.size()) + ", depth " +
                         std::to_string(view.depth.size()) + ", expected depth " +
                         std::to_string(view.expected_depth.size()) + ")");
  return {};
}

}  // namespace

float SrgbToLinear(float v) {
  // IEC 61966-2-1 decoding; the linear segment also serves negative values, the power law values above 1.
  const double s = v;
  return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

Status WriteViewExr(const splat::RenderedView& view, const std::string& path, ExrPixelType rgba_type) {
  if (Status s = CheckView(view, path); !s.ok()) return s;
  const std::size_t n = std::size_t(view.width) * view.height;
  const ExrPixelType kFloat = ExrPixelType::kFloat;
  const Plane planes[6] = {
      MakePlane(n, rgba_type, [&](std::size_t i) { return SrgbToLinear(view.rgb[3 * i + 0]); }),
      MakePlane(n, rgba_type, [&](std::size_t i) { return SrgbToLinear(view.rgb[3 * i + 1]); }),
      MakePlane(n, rgba_type, [&](std::size_t i) { return SrgbToLinear(view.rgb[3 * i + 2]); }),
      MakePlane(n, rgba_type, [&](std::size_t i) { return view.alpha[i]; }),
      MakePlane(n, kFloat, [&](std::size_t i) { return view.depth[i]; }),
      MakePlane(n, kFloat, [&](std::size_t i) { return view.expected_depth[i]; })};
  const char* names[6] = {"R", "G", "B", "A", "Z", kExrExpectedDepthChannel};
  const ExrPixelType types[6] = {rgba_type, rgba_type, rgba_type, rgba_type, kFloat, kFloat};

  Imf::Header header(view.width, view.height);  // data window = display window = the image
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  for (int c = 0; c < 6; ++c) {
    header.channels().insert(names[c], Imf::Channel(ToImf(types[c])));
    frame.insert(names[c], Imf::Slice::Make(ToImf(types[c]), planes[c].data(), header.dataWindow()));
  }
  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  try {
    Imf::StdOFStream stream(file.stream(), path.c_str());
    Imf::OutputFile out(stream, header);
    out.setFrameBuffer(frame);
    out.writePixels(view.height);
  } catch (const std::exception& e) {
    return Status::Error(path + ": writing the EXR failed: " + e.what());
  }
  return file.Commit();
}

Expected<ExrImage> ReadExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    ExrImage image;
    const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1;
    const std::int64_t height = std::int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > kMaxExrPixels)
      return Status::Error(path + ": EXR data window " + std::to_string(width) + " x " +
                           std::to_string(height) + " is empty or too large");
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    Imf::FrameBuffer frame;
    const Imf::ChannelList& channels = file.header().channels();
    std::int64_t count = 0;
    for (Imf::ChannelList::ConstIterator c = channels.begin(); c != channels.end(); ++c) ++count;
    if (count * width * height > kMaxExrPixels)
      return Status::Error(path + ": EXR holds " + std::to_string(count) + " channels of " +
                           std::to_string(width) + " x " + std::to_string(height) +
                           " pixels, too many to read");
    for (Imf::ChannelList::ConstIterator c = channels.begin(); c != channels.end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        return Status::Error(path + ": EXR channel '" + c.name() + "' is subsampled; not supported");
      std::vector<float>& plane = image.channels[c.name()];
      plane.assign(std::size_t(width * height), 0.0f);
      image.types[c.name()] = FromImf(c.channel().type);
      frame.insert(c.name(), Imf::Slice::Make(Imf::FLOAT, plane.data(), window));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    return Status::Error(path + ": cannot read the EXR: " + e.what());
  }
}

}  // namespace uf::exporting
