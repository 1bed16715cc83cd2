// The keypoint detector as a nodelet: RGB image + camera_info in, pose hypotheses out.
//
// Subscribes: image (rgb8/bgr8/rgba8/bgra8/mono8; raw or compressed: image_transport,
// ros/image_input.hpp) and camera_info, synchronised. Publishes:
// ~pose_hypotheses (PoseHypothesisArray, poses in the image's frame, stamped like the image) —
// what the tracker consumes — and ~debug_image (rgb8 with boxes, cuboids and keypoints) when
// someone subscribes to it. With `use_depth` (default true) it also subscribes to `depth` — a depth
// image registered to the RGB image (same size and intrinsics, 32FC1 m or 16UC1 mm; raw, compressed
// or compressedDepth: depth_transport) — and each
// accepted pose gets its distance from the depth image closest in time (within
// `depth_max_offset`, default 0.02 s): the range PnP on a few keypoints gets worst
// (detection/depth_translation.hpp). With `depth_max_wait` > 0 (default 0.3 s) an RGB image whose
// depth image may still come waits for it (ros/depth_pairing.hpp). Without such a depth image
// the distance stays PnP's and the nodelet warns. It detects on an image only when its schedule
// says so (detection/detection_schedule.hpp: often while tracks are tentative, lately lost or
// absent, at `settled_interval` while every track is confirmed), reading the tracks from
// `tracked_objects` (the tracker's ~tracked_objects); any other image gets an empty
// hypothesis array at once, so a tracker waiting for its image's array goes on. Parameters: the
// parameter schema (pipeline/parameter_schema.hpp), config/detector.yaml, doc/parameters.md; read
// at start. Bad input is warned about (throttled) and skipped; the nodelet keeps running. Counts of
// images in, published and skipped on /diagnostics ("scene_graph_tracker: detector"), once a
// second.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <memory>
#include <mutex>

#include "scene_graph_tracker/detection/detection_schedule.hpp"
#include "scene_graph_tracker/detection/pose_detector.hpp"
#include "scene_graph_tracker/ros/depth_pairing.hpp"
#include "scene_graph_tracker/ros/image_input.hpp"
#include "scene_graph_tracker/ros/warning_throttle.hpp"

namespace sgt::ros {

class DetectorNodelet : public nodelet::Nodelet {
 public:
  void onInit() override;

 private:
  using SyncPolicy =
      message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::CameraInfo>;
  void onImage(const sensor_msgs::ImageConstPtr& image,
               const sensor_msgs::CameraInfoConstPtr& info);
  void onDepth(const sensor_msgs::ImageConstPtr& depth);
  void onTracks(const scene_graph_tracker::TrackedObjectArray::ConstPtr& tracks);
  // Whether the schedule detects on the image; if not, publishes its empty array.
  bool scheduled(const std_msgs::Header& header, const cv::Mat& rgb);
  // The image for the schedule's view change (empty when new_view_share is off or it is bad).
  cv::Mat viewOf(const sensor_msgs::Image& image, const sensor_msgs::CameraInfo& info) const;
  void detect(const RgbFrame& frame);  // detects on the frame and publishes its hypotheses
  void onUndecodable(const std::string& text);
  // The buffered depth image closest to `stamp` within depth_max_offset, as range measurements of
  // `camera` (the RGB camera it is registered to); nullptr with a warning when there is none.
  std::unique_ptr<RangeMeasurements> registeredDepth(const ::ros::Time& stamp,
                                                     const PinholeModel& camera);
  void warn(const std::string& text);
  void publishDiagnostics();  // 1 Hz: the counts below

  std::unique_ptr<detection::PoseDetector> detector_;
  std::mutex mutex_;
  WarningThrottle warnings_;
  ImageInput image_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync_;
  ::ros::Publisher hypotheses_pub_, debug_pub_;
  ImageInput depth_sub_;  // with use_depth
  std::unique_ptr<DepthPairing> pairing_;
  ::ros::WallTimer pairing_timer_;  // ends a wait that no image or depth image ends
  PinholeRayCache depth_rays_;
  ::ros::Subscriber tracks_sub_;
  detection::DetectionSchedule schedule_;  // under mutex_
  struct Counts {                          // under mutex_
    std::size_t images_in = 0, published = 0, skipped = 0, depth_unused = 0, hypotheses = 0;
    std::size_t not_scheduled = 0;
    std::string last_problem;
  } counts_;
  ::ros::Publisher diagnostics_pub_;
  ::ros::WallTimer diagnostics_timer_;
};

}  // namespace sgt::ros
