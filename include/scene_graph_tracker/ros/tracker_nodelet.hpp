// The tracker as a nodelet: converts topics into pipeline frames, runs FramePipeline, publishes
// the results. No tracking logic lives here (see pipeline/frame_pipeline.hpp).
//
// Subscribes: depth image (raw, compressed or compressedDepth: depth_transport,
// ros/image_input.hpp)
// + camera_info (synchronised), a LiDAR PointCloud2 (its model from the lidar/* parameters), pose
// hypotheses (PoseHypothesisArray); frames through tf2. Publishes: ~tracked_objects, ~scene_graph,
// ~unassigned_points (PointCloud2 in the map frame), ~markers (MarkerArray), ~map_markers (the
// static map and furniture, latched), /diagnostics, TF
// map -> odom (publish_map_odom) and each track's frame below its scene-graph parent
// (publish_object_tf). Services: ~reset,
// ~add_track, ~remove_track. Parameters: the parameter schema (pipeline/parameter_schema.hpp),
// config/tracker.yaml, doc/parameters.md; most also at run time (dynamic_reconfigure,
// cfg/Tracker.cfg).
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <scene_graph_tracker/AddTrack.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <scene_graph_tracker/RemoveTrack.h>
#include <scene_graph_tracker/SceneGraph.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <scene_graph_tracker/TrackerConfig.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <deque>
#include <memory>
#include <mutex>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/pipeline/parameter_schema.hpp"
#include "scene_graph_tracker/ros/frame_assembler.hpp"
#include "scene_graph_tracker/ros/hypothesis_wait.hpp"
#include "scene_graph_tracker/ros/image_input.hpp"
#include "scene_graph_tracker/ros/stamp_order.hpp"
#include "scene_graph_tracker/ros/track_id_store.hpp"
#include "scene_graph_tracker/ros/warning_throttle.hpp"

namespace sgt::ros {

class TrackerNodelet : public nodelet::Nodelet {
 public:
  ~TrackerNodelet() override { depth_sub_.shutdown(); }  // before sync_, which it feeds, goes
  void onInit() override;

 private:
  void initialize();          // onInit's work; throws when the nodelet cannot start
  void shutDownInterfaces();  // every subscription, service and listener made so far
  using SyncPolicy =
      message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::CameraInfo>;

  void onDepth(const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::CameraInfoConstPtr& info);
  void processAll(const std::vector<DepthFrame>& frames);  // in order; each as processDepth
  void processDepth(const DepthFrame& frame);
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onLaserScan(const sensor_msgs::LaserScanConstPtr& scan);
  void onUndecodable(const std::string& text);
  void onHypotheses(const scene_graph_tracker::PoseHypothesisArrayConstPtr& msg);
  // Localization modes (tracker_localization.cpp).
  void setUpLocalization(const params::TrackerNodeOptions& node, PipelineOptions& options);
  void onInitialPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg);
  void applyExternalLocalization(const ::ros::Time& stamp);  // under mutex_
  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onAddTrack(scene_graph_tracker::AddTrack::Request& req,
                  scene_graph_tracker::AddTrack::Response& res);
  bool onRemoveTrack(scene_graph_tracker::RemoveTrack::Request& req,
                     scene_graph_tracker::RemoveTrack::Response& res);
  void publish(const PipelineResult& r, const ::ros::Time& stamp);
  scene_graph_tracker::TrackedObject trackedObjectMessage(const TrackedObject& o,
                                                          const TrackedObject* parent) const;
  scene_graph_tracker::SceneGraphNode graphNodeMessage(const TrackedObject& o,
                                                       const TrackedObject* parent) const;
  visualization_msgs::MarkerArray markers(const PipelineResult& r,
                                          const std_msgs::Header& header) const;
  static sensor_msgs::PointCloud2 unassignedPoints(const PipelineResult& r,
                                                   const std_msgs::Header& header);
  void publishDiagnostics(const std::string& problem, const PipelineResult* r);
  bool inOrder(StampVerdict verdict);  // false (counted, warned): a duplicate or out of order
  void saveTrackNumbers();             // track_ids_: when a class got a new track
  void waitForTransforms(const sensor_msgs::Image& depth);
  void warn(const std::string& text);
  void onReconfigure(scene_graph_tracker::TrackerConfig& config, std::uint32_t level);

  std::unique_ptr<FramePipeline> pipeline_;
  std::unique_ptr<FrameAssembler> assembler_;
  std::unique_ptr<HypothesisWait> hypothesis_wait_;  // depth frames until their detections came
  ::ros::WallTimer hypothesis_wait_timer_;
  std::mutex mutex_;  // pipeline_ and assembler_
  std::string map_frame_, odom_frame_, base_frame_;
  bool publish_map_odom_{}, publish_object_tf_{};  // params::TrackerNodeOptions (onInit)
  bool external_localization_{};                   // localization: external
  bool external_pose_ok_{};  // the last frame found map -> odom in TF (external localization)
  StampOrder stamps_;
  // What came in and what became of it, in /diagnostics.
  struct Counts {
    std::size_t frames_in = 0, processed = 0, skipped = 0, failed = 0, duplicates = 0,
                out_of_order = 0, time_jumps = 0, warnings = 0, hypotheses_over_limits = 0,
                hypotheses_duplicate = 0;
  } counts_;
  std::uint64_t published_ = 0;
  TrackIdStore track_ids_{""};
  std::map<std::string, int> saved_track_numbers_;  // frames published (header.seq of the outputs)
  WarningThrottle warnings_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  ImageInput depth_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync_;
  ::ros::Subscriber cloud_sub_, scan_sub_, hypotheses_sub_, initialpose_sub_;
  ::ros::Publisher objects_pub_, graph_pub_, unassigned_pub_, markers_pub_, map_markers_pub_,
      diagnostics_pub_;
  ::ros::ServiceServer reset_srv_, add_srv_, remove_srv_;
  std::unique_ptr<dynamic_reconfigure::Server<scene_graph_tracker::TrackerConfig>> reconfigure_;
  boost::recursive_mutex reconfigure_mutex_;
};

}  // namespace sgt::ros
