#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "odometry/io/image_decode.h"

namespace uf {
namespace {

// A 7x5 BGR test pattern whose every byte differs, so a channel or row mix-up shows.
cv::Mat Pattern() {
  cv::Mat bgr(5, 7, CV_8UC3);
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c < bgr.cols; ++c)
      bgr.at<cv::Vec3b>(r, c) = cv::Vec3b(r * 40 + c, 100 + c * 10, 255 - r * 7 - c);
  }
  return bgr;
}

void ExpectRgbOf(const Image& image, const cv::Mat& bgr) {
  ASSERT_EQ(image.width, bgr.cols);
  ASSERT_EQ(image.height, bgr.rows);
  ASSERT_EQ(image.channels, 3);
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c < bgr.cols; ++c) {
      const std::uint8_t* px = &image.pixels[(std::size_t(r) * image.width + c) * 3];
      const cv::Vec3b& expected = bgr.at<cv::Vec3b>(r, c);
      ASSERT_EQ(px[0], expected[2]);
      ASSERT_EQ(px[1], expected[1]);
      ASSERT_EQ(px[2], expected[0]);
    }
  }
}

TEST(ImageDecode, PngBecomesRgb) {
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", Pattern(), png));
  EncodedImage encoded{"png", 0, 0, 0, png};
  Expected<Image> image = DecodeImage(encoded);
  ASSERT_TRUE(image.ok()) << image.error();
  ExpectRgbOf(*image, Pattern());
}

TEST(ImageDecode, RawBgr8WithRowPadding) {
  const cv::Mat bgr = Pattern();
  EncodedImage encoded{"bgr8", bgr.cols, bgr.rows, bgr.cols * 3 + 5, {}};
  encoded.bytes.assign(std::size_t(encoded.row_step) * bgr.rows, 0xAB);
  for (int r = 0; r < bgr.rows; ++r)
    std::memcpy(&encoded.bytes[r * encoded.row_step], bgr.ptr(r), bgr.cols * 3);
  Expected<Image> image = DecodeImage(encoded);
  ASSERT_TRUE(image.ok()) << image.error();
  ExpectRgbOf(*image, bgr);
}

TEST(ImageDecode, Mono16KeepsTheHighByte) {
  EncodedImage encoded{"mono16", 2, 1, 4, {0x34, 0x12, 0xFF, 0x80}};  // little-endian 0x1234, 0x80FF
  Expected<Image> image = DecodeImage(encoded);
  ASSERT_TRUE(image.ok()) << image.error();
  EXPECT_EQ(image->channels, 1);
  EXPECT_EQ(image->pixels, (std::vector<std::uint8_t>{0x12, 0x80}));
}

TEST(ImageDecode, ShortRawDataIsAnError) {
  EncodedImage encoded{"rgb8", 4, 4, 12, std::vector<std::uint8_t>(40)};
  Expected<Image> image = DecodeImage(encoded);
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.error().find("40 bytes, expected row_step*height = 48"), std::string::npos)
      << image.error();
}

TEST(ImageDecode, CorruptPngIsAnError) {
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", Pattern(), png));
  png.resize(png.size() / 3);
  Expected<Image> image = DecodeImage(EncodedImage{"png", 0, 0, 0, png});
  EXPECT_FALSE(image.ok());
}

TEST(ImageDecode, CameraFrameIsDecodedOnceAndReleasesItsBytes) {
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", Pattern(), png));
  CameraFrame frame;
  frame.encoded = EncodedImage{"png", 0, 0, 0, png};
  ASSERT_TRUE(DecodeCameraFrame(frame).ok());
  EXPECT_TRUE(frame.encoded.empty());
  ExpectRgbOf(frame.image, Pattern());
  EXPECT_TRUE(DecodeCameraFrame(frame).ok());
}

}  // namespace
}  // namespace uf
