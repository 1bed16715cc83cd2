// sensor_msgs/CompressedImage as image_transport's plugins write it (what a robot's bags hold),
// decoded to a raw sensor_msgs/Image that the rest of the package reads:
//   "compressed"       JPEG or PNG colour / mono (format e.g. "rgb8; jpeg compressed bgr8"):
//                      bgr8 or mono8 (8-bit), 16UC1 (a 16-bit PNG); decoded by cv_bridge
//   "compressedDepth"  a 12-byte header (format, two quantisation parameters), then a PNG:
//                      "16UC1; compressedDepth png": millimetres as they are; "32FC1;
//                      compressedDepth": inverse depth, depth = a / (value - b) metres, 0 = no
//                      return (NaN)
// Offline readers (the bag reader) use this; the live nodes subscribe through image_transport.
#pragma once

#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

namespace sgt::ros {

// Throws ConversionError (conversions.hpp) naming the problem: an unknown format, data that does
// not decode, a header that is too short.
sensor_msgs::Image decompress(const sensor_msgs::CompressedImage& c);

}  // namespace sgt::ros
