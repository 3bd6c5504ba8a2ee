#include "odometry/io/image_decode.h"

#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace uf {
namespace {

struct RawLayout {
  int bytes_per_channel;
  int channels;
  bool bgr_order;  // channels stored B G R (A)
};

bool LookupRawLayout(const std::string& encoding, RawLayout& layout) {
  if (encoding == "mono8" || encoding == "8UC1")
    layout = {1, 1, false};
  else if (encoding == "mono16" || encoding == "16UC1")
    layout = {2, 1, false};
  else if (encoding == "rgb8")
    layout = {1, 3, false};
  else if (encoding == "bgr8" || encoding == "8UC3")
    layout = {1, 3, true};
  else if (encoding == "rgba8")
    layout = {1, 4, false};
  else if (encoding == "bgra8")
    layout = {1, 4, true};
  else
    return false;
  return true;
}

// Raw pixel rows (with row_step padding) into a tightly packed 8-bit gray or RGB image.
Expected<Image> DecodeRaw(const EncodedImage& encoded, const RawLayout& layout) {
  const std::int64_t pixel_bytes = std::int64_t{layout.bytes_per_channel} * layout.channels;
  if (encoded.width <= 0 || encoded.height <= 0 || encoded.row_step < encoded.width * pixel_bytes) {
    return Status::Error("image '" + encoded.format + "': bad size " + std::to_string(encoded.width) + "x" +
                         std::to_string(encoded.height) + " with row_step " +
                         std::to_string(encoded.row_step));
  }
  const std::int64_t needed = std::int64_t{encoded.row_step} * encoded.height;
  if (static_cast<std::int64_t>(encoded.bytes.size()) < needed) {
    return Status::Error("image '" + encoded.format + "': data has " + std::to_string(encoded.bytes.size()) +
                         " bytes, expected row_step*height = " + std::to_string(needed));
  }
  Image image;
  image.width = encoded.width;
  image.height = encoded.height;
  image.channels = layout.channels == 1 ? 1 : 3;
  image.pixels.resize(std::size_t(image.width) * image.height * image.channels);
  std::uint8_t* out = image.pixels.data();
  for (int row = 0; row < image.height; ++row) {
    const std::uint8_t* in = encoded.bytes.data() + std::size_t(row) * encoded.row_step;
    for (int col = 0; col < image.width; ++col, in += pixel_bytes) {
      // 16-bit samples are little-endian (ROS is_bigendian = 0 in practice); keep the high byte.
      const auto sample = [&](int c) {
        return in[c * layout.bytes_per_channel + layout.bytes_per_channel - 1];
      };
      if (image.channels == 1) {
        *out++ = sample(0);
      } else {
        *out++ = sample(layout.bgr_order ? 2 : 0);
        *out++ = sample(1);
        *out++ = sample(layout.bgr_order ? 0 : 2);
      }
    }
  }
  return image;
}

Expected<Image> DecodeCompressed(const EncodedImage& encoded) {
  cv::Mat decoded;
  try {
    const cv::Mat bytes(1, static_cast<int>(encoded.bytes.size()), CV_8UC1,
                        const_cast<std::uint8_t*>(encoded.bytes.data()));
    decoded = cv::imdecode(bytes, cv::IMREAD_ANYCOLOR);  // 8-bit, gray or BGR
  } catch (const cv::Exception& e) {
    return Status::Error("image '" + encoded.format + "': " + e.what());
  }
  if (decoded.empty()) {
    return Status::Error("image '" + encoded.format + "': cannot decode " +
                         std::to_string(encoded.bytes.size()) + " bytes (corrupt or unsupported)");
  }
  Image image;
  image.width = decoded.cols;
  image.height = decoded.rows;
  image.channels = decoded.channels() == 1 ? 1 : 3;
  image.pixels.resize(std::size_t(image.width) * image.height * image.channels);
  std::uint8_t* out = image.pixels.data();
  for (int row = 0; row < decoded.rows; ++row) {
    const std::uint8_t* in = decoded.ptr<std::uint8_t>(row);
    for (int col = 0; col < decoded.cols; ++col, in += decoded.channels()) {
      if (image.channels == 1) {
        *out++ = in[0];
      } else {  // OpenCV gives B G R
        *out++ = in[2];
        *out++ = in[1];
        *out++ = in[0];
      }
    }
  }
  return image;
}

}  // namespace

Expected<Image> DecodeImage(const EncodedImage& encoded) {
  if (encoded.empty()) return Status::Error("image '" + encoded.format + "': no data");
  RawLayout layout;
  if (LookupRawLayout(encoded.format, layout)) return DecodeRaw(encoded, layout);
  return DecodeCompressed(encoded);
}

Status DecodeCameraFrame(CameraFrame& frame) {
  if (!frame.image.empty()) return {};
  Expected<Image> image = DecodeImage(frame.encoded);
  if (!image) return image.status();
  frame.image = std::move(*image);
  frame.encoded = EncodedImage{};
  return {};
}

Expected<std::vector<std::uint8_t>> EncodePng(const Image& image, const std::string& where) {
  if (image.width <= 0 || image.height <= 0 || (image.channels != 1 && image.channels != 3) ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * image.channels)
    return Status::Error(where + ": the decoded image is inconsistent (width, height, channels, pixels)");
  cv::Mat mat(image.height, image.width, image.channels == 1 ? CV_8UC1 : CV_8UC3);
  std::copy(image.pixels.begin(), image.pixels.end(), mat.data);
  if (image.channels == 3)  // OpenCV wants BGR
    for (std::size_t i = 0; i < image.pixels.size(); i += 3) std::swap(mat.data[i], mat.data[i + 2]);
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", mat, png, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    return Status::Error(where + ": PNG encoding failed");
  return png;
}

Expected<Image> ReadImageFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::Error(path.string() + ": cannot open");
  EncodedImage encoded;
  encoded.format = "png";  // any format imdecode recognises by its bytes
  encoded.bytes.assign(std::istreambuf_iterator<char>(file), {});
  if (encoded.bytes.empty()) return Status::Error(path.string() + ": empty");
  Expected<Image> image = DecodeImage(encoded);
  if (!image) return Status::Error(path.string() + ": " + image.error());
  return image;
}

Expected<Image> ReadMaskFile(const std::filesystem::path& path, int width, int height) {
  Expected<Image> image = ReadImageFile(path);
  if (!image) return image.status();
  if (image->width != width || image->height != height)
    return Status::Error(path.string() + " is " + std::to_string(image->width) + " x " +
                         std::to_string(image->height) + " px, the camera " + std::to_string(width) + " x " +
                         std::to_string(height));
  Image mask{width, height, 1, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height)};
  for (std::size_t p = 0; p < mask.pixels.size(); ++p)
    mask.pixels[p] = image->pixels[p * image->channels] < 128 ? 0 : 255;
  return mask;
}

}  // namespace uf
