#include "scene_graph_tracker/ros/compressed_images.hpp"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scene_graph_tracker/ros/conversions.hpp"

namespace sgt::ros {
namespace {

namespace enc = sensor_msgs::image_encodings;

constexpr std::size_t kDepthHeaderBytes = 12;  // int32 format, float quantisation a, b

sensor_msgs::Image compressedDepth(const sensor_msgs::CompressedImage& c) {
  if (c.data.size() <= kDepthHeaderBytes)
    throw ConversionError("compressedDepth image shorter than its 12-byte header");
  float quant[2];
  std::memcpy(quant, c.data.data() + 4, sizeof quant);
  const cv::Mat png(1, static_cast<int>(c.data.size() - kDepthHeaderBytes), CV_8UC1,
                    const_cast<std::uint8_t*>(c.data.data() + kDepthHeaderBytes));
  const cv::Mat raw = cv::imdecode(png, cv::IMREAD_UNCHANGED);
  if (raw.empty() || raw.type() != CV_16UC1)
    throw ConversionError("compressedDepth data is not a 16-bit PNG");
  cv_bridge::CvImage out;
  out.header = c.header;
  if (c.format.rfind("16UC1", 0) == 0) {
    out.encoding = enc::TYPE_16UC1, out.image = raw;
  } else if (c.format.rfind("32FC1", 0) == 0) {
    out.encoding = enc::TYPE_32FC1;
    out.image = cv::Mat(raw.size(), CV_32FC1);
    raw.forEach<std::uint16_t>([&](std::uint16_t v, const int* p) {
      out.image.at<float>(p[0], p[1]) =
          v == 0 ? NAN : quant[0] / (static_cast<float>(v) - quant[1]);
    });
  } else {
    throw ConversionError("compressedDepth format '" + c.format + "' is not 16UC1 or 32FC1");
  }
  return *out.toImageMsg();
}

}  // namespace

sensor_msgs::Image decompress(const sensor_msgs::CompressedImage& c) {
  if (c.format.find("compressedDepth") != std::string::npos) return compressedDepth(c);
  try {
    const cv_bridge::CvImagePtr img = cv_bridge::toCvCopy(c);
    if (img->image.empty()) throw ConversionError("compressed image does not decode");
    return *img->toImageMsg();
  } catch (const cv_bridge::Exception& e) {
    throw ConversionError(std::string("compressed image (") + c.format + "): " + e.what());
  } catch (const cv::Exception& e) {
    throw ConversionError(std::string("compressed image (") + c.format + "): " + e.what());
  }
}

// compressed_depth_image_transport's layout: a 12-byte header (format, two quantisation
// parameters; unused for 16-bit depth) and the PNG.
sensor_msgs::CompressedImage compressDepthMillimetres(const std_msgs::Header& h,
                                                      const cv::Mat& mm) {
  sensor_msgs::CompressedImage c;
  c.header = h;
  c.format = "16UC1; compressedDepth png";
  std::vector<std::uint8_t> png;
  cv::imencode(".png", mm, png);
  c.data.assign(kDepthHeaderBytes, 0);
  c.data.insert(c.data.end(), png.begin(), png.end());
  return c;
}

sensor_msgs::CompressedImage compressRgbJpeg(const std_msgs::Header& h, const cv::Mat& rgb,
                                             int quality) {
  sensor_msgs::CompressedImage c;
  c.header = h;
  c.format = "rgb8; jpeg compressed bgr8";
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  cv::imencode(".jpg", bgr, c.data, {cv::IMWRITE_JPEG_QUALITY, quality});
  return c;
}

}  // namespace sgt::ros
