// Depth, RGB and CameraInfo conversion: toPinhole on a CameraInfo from the bytes, then an image
// that is either raw (sensor_msgs/Image: encoding, size, step, endianness, data from the bytes)
// or compressed (sensor_msgs/CompressedImage: format and data from the bytes, through
// decompress), into depthFromImage and rgbFromImage. The bytes: the info and the image's layout
// (from the end), then the pixel data or the compressed stream (from the front).
#include <sensor_msgs/image_encodings.h>

#include <opencv2/core.hpp>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/ros/compressed_images.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"

namespace {

using sgt::fuzz::count;
using sgt::fuzz::name;
using sgt::fuzz::number;

// An image side: mostly small, sometimes up to the largest camera toPinhole takes, or anything.
std::uint32_t side(FuzzedDataProvider& p, std::uint32_t usual) {
  switch (p.ConsumeIntegralInRange<int>(0, 7)) {
    case 0:
      return p.ConsumeIntegral<std::uint32_t>();
    case 1:
      return p.ConsumeIntegralInRange<std::uint32_t>(0, 16384);
    default:
      return p.ConsumeIntegralInRange<std::uint32_t>(0, usual);
  }
}

sensor_msgs::CameraInfo cameraInfo(FuzzedDataProvider& p) {
  sensor_msgs::CameraInfo info;
  info.width = side(p, 64), info.height = side(p, 48);
  const bool sane = p.ConsumeIntegralInRange<int>(0, 3) != 0;
  info.K[0] = sane ? p.ConsumeFloatingPointInRange(1.0, 200.0) : number(p, 200.0);
  info.K[4] = sane ? p.ConsumeFloatingPointInRange(1.0, 200.0) : number(p, 200.0);
  info.K[2] = sane ? 0.5 * info.width : number(p, 100.0);
  info.K[5] = sane ? 0.5 * info.height : number(p, 100.0);
  info.K[8] = 1.0;
  return info;
}

// Bytes per pixel of the encodings the conversions know (0: another one).
std::size_t bytesPerPixel(const std::string& e) {
  namespace enc = sensor_msgs::image_encodings;
  if (e == enc::TYPE_32FC1 || e == enc::RGBA8 || e == enc::BGRA8) return 4;
  if (e == enc::TYPE_16UC1 || e == enc::MONO16) return 2;
  if (e == enc::RGB8 || e == enc::BGR8) return 3;
  if (e == enc::MONO8) return 1;
  return 0;
}

sensor_msgs::Image rawImage(FuzzedDataProvider& p, const sgt::PinholeModel& cam) {
  sensor_msgs::Image img;
  img.encoding = name(p, {"32FC1", "16UC1", "mono16", "rgb8", "bgr8", "rgba8", "bgra8", "mono8",
                          "8UC3", "16UC3", "32FC3", "bayer_rggb8", "yuv422", "64FC1"});
  const bool fits = p.ConsumeIntegralInRange<int>(0, 3) != 0;  // the camera's size
  img.width = fits ? cam.width : side(p, 64);
  img.height = fits ? cam.height : side(p, 48);
  img.is_bigendian = p.ConsumeIntegralInRange<int>(0, 7) == 0;
  const std::uint64_t bpp = bytesPerPixel(img.encoding);
  const std::uint64_t row = img.width * (bpp ? bpp : 3);
  const bool consistent = p.ConsumeIntegralInRange<int>(0, 3) != 0 && row <= UINT32_MAX &&
                          row * img.height <= (1u << 20);
  img.step = consistent ? static_cast<std::uint32_t>(row) : count<std::uint32_t>(p, 1024);
  std::vector<std::uint8_t> bytes = p.ConsumeRemainingBytes<std::uint8_t>();
  if (consistent) {  // the pixel data repeated to fill the image (the harness's own allocation
                     // stays within 1 MB)
    img.data.resize(std::uint64_t(img.step) * img.height);
    for (std::size_t i = 0; !bytes.empty() && i < img.data.size(); ++i)
      img.data[i] = bytes[i % bytes.size()];
  } else {
    img.data = std::move(bytes);
  }
  return img;
}

bool compressedImage(FuzzedDataProvider& p, sensor_msgs::Image& img) {
  sensor_msgs::CompressedImage c;
  c.format = name(
      p, {"jpeg", "png", "rgb8; jpeg compressed bgr8", "bgr8; png compressed bgr8",
          "mono8; png compressed mono8", "16UC1; png compressed", "mono16; png compressed mono16",
          "16UC1; compressedDepth png", "32FC1; compressedDepth", "32FC1; compressedDepth png",
          "rgba8; jpeg compressed bgr8", "bgr8; compressedDepth", "compressedDepth"});
  c.data = p.ConsumeRemainingBytes<std::uint8_t>();
  try {
    img = sgt::ros::decompress(c);
  } catch (const sgt::ros::ConversionError&) {
    return false;
  }
  sgt::fuzz::expect(img.step >= img.width && img.data.size() >= std::size_t(img.step) * img.height,
                    "a decompressed image holds its rows");
  return true;
}

}  // namespace

int sgtFuzzImages(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  const bool compressed = p.ConsumeBool();
  const sensor_msgs::CameraInfo info = cameraInfo(p);
  sgt::PinholeModel cam;
  try {
    cam = sgt::ros::toPinhole(info);
    sgt::fuzz::expect(cam.width > 0 && cam.height > 0 && cam.fx > 0 && cam.fy > 0,
                      "a camera with pixels and focal lengths");
  } catch (const sgt::ros::ConversionError&) {
    cam.width = 64, cam.height = 48;  // go on with the images against a small camera
  }
  sensor_msgs::Image img;
  if (compressed) {
    if (!compressedImage(p, img)) return 0;
    if (img.width > 0 && img.height > 0 && img.width <= 16384 && img.height <= 16384)
      cam.width = static_cast<int>(img.width), cam.height = static_cast<int>(img.height);
  } else {
    img = rawImage(p, cam);
  }
  try {
    const std::vector<float> depth = sgt::ros::depthFromImage(img, cam);
    sgt::fuzz::expect(depth.size() == std::size_t(cam.width) * cam.height, "a depth per pixel");
  } catch (const sgt::ros::ConversionError&) {
  }
  try {
    const cv::Mat rgb = sgt::ros::rgbFromImage(img, cam);
    sgt::fuzz::expect(rgb.type() == CV_8UC3 && rgb.cols == cam.width && rgb.rows == cam.height,
                      "an 8-bit RGB image of the camera's size");
  } catch (const sgt::ros::ConversionError&) {
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzImages)
