// sensor_msgs/CompressedImage as image_transport's plugins write it (what a robot's bags hold),
// decoded to a raw sensor_msgs/Image that the rest of the package reads:
//   "compressed"       JPEG or PNG colour / mono (format e.g. "rgb8; jpeg compressed bgr8"):
//                      bgr8 or mono8 (8-bit), 16UC1 (a 16-bit PNG); decoded by cv_bridge
//   "compressedDepth"  a 12-byte header (format, two quantisation parameters), then a PNG:
//                      "16UC1; compressedDepth png": millimetres as they are; "32FC1;
//                      compressedDepth": inverse depth, depth = a / (value - b) metres, 0 = no
//                      return (NaN)
// The bag reader uses this; the live nodes subscribe through image_transport and use this where
// image_transport has no plugin for the transport (ros/image_input.hpp).
#pragma once

#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <opencv2/core.hpp>

namespace sgt::ros {

// Throws ConversionError (conversions.hpp) naming the problem: an unknown format, data that does
// not decode, a header that is too short.
sensor_msgs::Image decompress(const sensor_msgs::CompressedImage& c);

// The other way, as the plugins write them (the sequence bag writer, tests): 16-bit millimetres
// (CV_16UC1, 0 = no return) as "16UC1; compressedDepth png", lossless; an RGB image (CV_8UC3) as
// "rgb8; jpeg compressed bgr8".
sensor_msgs::CompressedImage compressDepthMillimetres(const std_msgs::Header& h, const cv::Mat& mm);
sensor_msgs::CompressedImage compressRgbJpeg(const std_msgs::Header& h, const cv::Mat& rgb,
                                             int quality = 95);

}  // namespace sgt::ros
