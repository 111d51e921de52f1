#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/detector_opencv.hpp"
#include "detect/image.hpp"

namespace test_image {

using namespace tagbench;

TEST(Image, RowMajorAccessAndClampedBorders) {
  ImageF img(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) img.at(x, y) = static_cast<float>(10 * y + x);
  EXPECT_EQ(img.data[1 * 3 + 2], 12.0f);
  EXPECT_EQ(img.at_clamped(-5, 0), 0.0f);
  EXPECT_EQ(img.at_clamped(7, -1), 2.0f);
  EXPECT_EQ(img.at_clamped(1, 9), 11.0f);
  EXPECT_FALSE(img.empty());
  EXPECT_TRUE(ImageF().empty());
}

TEST(Image, EightBitIsScaledBy255) {
  cv::Mat m(1, 3, CV_8UC1);
  m.at<uchar>(0, 0) = 0;
  m.at<uchar>(0, 1) = 51;
  m.at<uchar>(0, 2) = 255;
  const ImageF f = to_float_image(m);
  ASSERT_EQ(f.width, 3);
  ASSERT_EQ(f.height, 1);
  EXPECT_FLOAT_EQ(f.at(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(f.at(1, 0), 0.2f);
  EXPECT_FLOAT_EQ(f.at(2, 0), 1.0f);
}

TEST(Image, SixteenBitIsScaledBy65535) {
  cv::Mat m(2, 1, CV_16UC1);
  m.at<ushort>(0, 0) = 65535;
  m.at<ushort>(1, 0) = 13107;  // 65535 / 5
  const ImageF f = to_float_image(m);
  ASSERT_EQ(f.width, 1);
  ASSERT_EQ(f.height, 2);
  EXPECT_FLOAT_EQ(f.at(0, 0), 1.0f);
  EXPECT_FLOAT_EQ(f.at(0, 1), 0.2f);
}

// OpenCV stores colour as BGR: pure red must come out as the red weight 0.299, not the blue 0.114.
TEST(Image, ColourIsBgrWithLumaWeights) {
  cv::Mat m(1, 3, CV_8UC3);
  m.at<cv::Vec3b>(0, 0) = {0, 0, 255};  // red
  m.at<cv::Vec3b>(0, 1) = {0, 255, 0};  // green
  m.at<cv::Vec3b>(0, 2) = {255, 0, 0};  // blue
  const ImageF f = to_float_image(m);
  EXPECT_NEAR(f.at(0, 0), 0.299f, 1e-3);
  EXPECT_NEAR(f.at(1, 0), 0.587f, 1e-3);
  EXPECT_NEAR(f.at(2, 0), 0.114f, 1e-3);

  cv::Mat a(1, 1, CV_8UC4, cv::Scalar(0, 0, 255, 7));  // BGRA red, alpha ignored
  EXPECT_NEAR(to_float_image(a).at(0, 0), 0.299f, 1e-3);
}

// A 16-bit colour value that is not a multiple of 257 must not be rounded to 8 bits first.
TEST(Image, SixteenBitColourKeepsPrecision) {
  cv::Mat m(1, 1, CV_16UC3, cv::Scalar(1000, 1000, 1000));
  EXPECT_NEAR(to_float_image(m).at(0, 0), 1000.0 / 65535.0, 1e-6);
}

TEST(Image, NonContinuousRoiIsCopiedRowByRow) {
  cv::Mat big(4, 5, CV_8UC1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) big.at<uchar>(y, x) = static_cast<uchar>(10 * y + x);
  const cv::Mat roi = big(cv::Rect(1, 1, 3, 2));
  ASSERT_FALSE(roi.isContinuous());
  const ImageF f = to_float_image(roi);
  ASSERT_EQ(f.width, 3);
  ASSERT_EQ(f.height, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) EXPECT_FLOAT_EQ(f.at(x, y), (10 * (y + 1) + (x + 1)) / 255.0f);
}

TEST(Image, FloatInputIsTakenAsIs) {
  cv::Mat m(1, 1, CV_32FC1, cv::Scalar(0.375));
  EXPECT_FLOAT_EQ(to_float_image(m).at(0, 0), 0.375f);
}

TEST(Image, UnsupportedInputsThrow) {
  EXPECT_THROW(to_float_image(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(to_float_image(cv::Mat(2, 2, CV_64FC1, cv::Scalar(0.5))), std::invalid_argument);
  EXPECT_THROW(to_float_image(cv::Mat(2, 2, CV_8UC2, cv::Scalar(1, 2))), std::invalid_argument);
}

// The 8-bit buffer entry point (ImageU8View) gives the detector the very floats the cv::Mat path
// gives: every value, with a stride past the width, bit for bit.
TEST(Image, EightBitViewMatchesTheMatConversionBitForBit) {
  const int w = 256, h = 3, stride = 260;
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(stride) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) buf[static_cast<std::size_t>(y) * stride + x] = static_cast<std::uint8_t>((x + 97 * y) & 255);
  const cv::Mat m(h, w, CV_8UC1, buf.data(), static_cast<std::size_t>(stride));
  const ImageF from_mat = to_float_image(m);
  const ImageF from_view = to_float_image(ImageU8View{w, h, stride, buf.data()});
  ASSERT_EQ(from_view.width, w);
  ASSERT_EQ(from_view.height, h);
  ASSERT_EQ(from_view.data.size(), from_mat.data.size());
  for (std::size_t i = 0; i < from_mat.data.size(); ++i)
    ASSERT_EQ(std::memcmp(&from_view.data[i], &from_mat.data[i], sizeof(float)), 0) << "pixel " << i;
}

TEST(Image, BadEightBitViewsThrow) {
  const std::uint8_t px[4] = {1, 2, 3, 4};
  EXPECT_THROW(to_float_image(ImageU8View{}), std::invalid_argument);
  EXPECT_THROW(to_float_image(ImageU8View{2, 2, 2, nullptr}), std::invalid_argument);
  EXPECT_THROW(to_float_image(ImageU8View{2, 0, 2, px}), std::invalid_argument);
  EXPECT_THROW(to_float_image(ImageU8View{2, 2, 1, px}), std::invalid_argument);
  EXPECT_EQ(to_float_image(ImageU8View{2, 2, 2, px}).at(1, 1), 4.0f * static_cast<float>(1.0 / 255.0));
}

}  // namespace test_image
