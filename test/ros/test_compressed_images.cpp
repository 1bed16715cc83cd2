// Compressed images as image_transport's plugins write them, decoded for the bag reader:
// compressedDepth 16UC1 (millimetres, lossless) and 32FC1 (inverse depth), JPEG colour, and
// broken messages rejected with a reason.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

sensor_msgs::CompressedImage depthMessage(const std::string& format, const cv::Mat& png16,
                                          float a = 0.0f, float b = 0.0f) {
  sensor_msgs::CompressedImage c;
  c.format = format;
  c.data.assign(12, 0);
  std::memcpy(c.data.data() + 4, &a, 4);
  std::memcpy(c.data.data() + 8, &b, 4);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", png16, png);
  c.data.insert(c.data.end(), png.begin(), png.end());
  return c;
}

TEST(CompressedImages, DepthInMillimetresDecodesExactly) {
  cv::Mat mm(4, 6, CV_16UC1, cv::Scalar(1234));
  mm.at<std::uint16_t>(1, 2) = 0;  // no return
  const sensor_msgs::Image img = decompress(depthMessage("16UC1; compressedDepth png", mm));
  EXPECT_EQ(img.encoding, sensor_msgs::image_encodings::TYPE_16UC1);
  PinholeModel cam;
  cam.width = 6, cam.height = 4;
  const std::vector<float> depth = depthFromImage(img, cam);
  EXPECT_FLOAT_EQ(depth[0], 1.234f);
  EXPECT_TRUE(std::isnan(depth[1 * 6 + 2]));
}

TEST(CompressedImages, MillimetresRoundTripThroughTheEncoder) {
  cv::Mat mm(3, 5, CV_16UC1, cv::Scalar(2500));
  mm.at<std::uint16_t>(2, 4) = 0;
  std_msgs::Header h;
  h.frame_id = "camera", h.seq = 7;
  const sensor_msgs::Image img = decompress(compressDepthMillimetres(h, mm));
  EXPECT_EQ(img.header.frame_id, "camera");
  EXPECT_EQ(img.header.seq, 7u);
  PinholeModel cam;
  cam.width = 5, cam.height = 3;
  const std::vector<float> depth = depthFromImage(img, cam);
  EXPECT_FLOAT_EQ(depth[0], 2.5f);
  EXPECT_TRUE(std::isnan(depth[2 * 5 + 4]));
}

TEST(CompressedImages, InverseDepthIsQuantisedBack) {
  // image_transport stores depth d as a / d + b; here a = 1000, b = 10: 2 m is 510.
  cv::Mat q(2, 2, CV_16UC1, cv::Scalar(510));
  q.at<std::uint16_t>(0, 1) = 0;
  const sensor_msgs::Image img = decompress(depthMessage("32FC1; compressedDepth", q, 1000, 10));
  ASSERT_EQ(img.encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  float d[4];
  std::memcpy(d, img.data.data(), sizeof d);
  EXPECT_FLOAT_EQ(d[0], 2.0f);
  EXPECT_TRUE(std::isnan(d[1]));
}

TEST(CompressedImages, JpegColourDecodes) {
  sensor_msgs::CompressedImage c;
  c.format = "rgb8; jpeg compressed bgr8";
  cv::imencode(".jpg", cv::Mat(8, 10, CV_8UC3, cv::Scalar(20, 100, 200)), c.data);  // BGR
  const sensor_msgs::Image img = decompress(c);
  PinholeModel cam;
  cam.width = 10, cam.height = 8;
  const cv::Mat rgb = rgbFromImage(img, cam);
  EXPECT_NEAR(rgb.at<cv::Vec3b>(4, 5)[0], 200, 3);
  EXPECT_NEAR(rgb.at<cv::Vec3b>(4, 5)[2], 20, 3);
}

TEST(CompressedImages, BrokenMessagesAreRejectedWithAReason) {
  sensor_msgs::CompressedImage c;
  c.format = "16UC1; compressedDepth png";
  c.data.assign(5, 0);
  EXPECT_THROW(decompress(c), ConversionError);  // shorter than the header
  c.data.assign(40, 7);
  EXPECT_THROW(decompress(c), ConversionError);  // no PNG after it
  const cv::Mat mm(2, 2, CV_16UC1, cv::Scalar(5));
  EXPECT_THROW(decompress(depthMessage("8UC3; compressedDepth", mm)), ConversionError);
  sensor_msgs::CompressedImage jpeg;
  jpeg.format = "jpeg";
  jpeg.data = {1, 2, 3, 4};
  EXPECT_THROW(decompress(jpeg), ConversionError);
}

}  // namespace
}  // namespace sgt::ros
