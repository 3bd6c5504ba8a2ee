// Encoding and decoding of camera images. Decoding is done lazily: readers keep the bytes as read
// (CameraFrame::encoded) and the consumer decodes the frames it actually uses. Output is 8-bit gray or RGB
// (see uf::Image).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "odometry/types/measurements.h"
#include "odometry/types/status.h"

namespace uf {

// PNG/JPEG (any format OpenCV reads; 16-bit scaled to 8-bit, alpha dropped) or a raw ROS encoding:
// mono8, 8UC1, mono16, 16UC1, rgb8, bgr8, 8UC3 (taken as bgr, OpenCV's order), rgba8, bgra8.
Expected<Image> DecodeImage(const EncodedImage& encoded);

// Reads and decodes an image file (any format DecodeImage reads); errors name the path.
Expected<Image> ReadImageFile(const std::filesystem::path& path);

// A mask of a camera (black pixels masked: the ego vehicle, a hood) read from an image file: one channel,
// 0 where the file's first channel is below 128, else 255. Errors name the path; an image of another size
// than width x height: "PATH is W x H px, the camera W x H".
Expected<Image> ReadMaskFile(const std::filesystem::path& path, int width, int height);

// Decodes frame.encoded into frame.image (no-op when the image is already decoded) and frees the bytes.
Status DecodeCameraFrame(CameraFrame& frame);

// PNG bytes of an 8-bit gray or RGB image, with fast (level 1) compression; errors start with `where`.
Expected<std::vector<std::uint8_t>> EncodePng(const Image& image, const std::string& where);

}  // namespace uf
