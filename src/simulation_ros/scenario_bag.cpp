#include "scene_graph_tracker/simulation/scenario_bag.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <scene_graph_tracker/ObjectPoseArray.h>
#include <scene_graph_tracker/PoseHypothesisArray.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <boost/make_shared.hpp>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "bag_messages.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/simulation/scenario_world.hpp"

namespace sgt::ros {
namespace {

// Everything written at one sensor stamp.
struct Bundle {
  ::ros::Time stamp;
  tf2_msgs::TFMessage tf;
  geometry_msgs::PoseStamped base;
  bool camera = false;
  sensor_msgs::Image rgb, depth, depth_labels;
  sensor_msgs::CameraInfo info;
  scene_graph_tracker::ObjectPoseArray truth;
  scene_graph_tracker::PoseHypothesisArray hypotheses;
  bool lidar = false;
  sensor_msgs::PointCloud2 cloud;
  sensor_msgs::Image lidar_labels;
};

// A small blocking queue between the simulating thread and the writing thread.
class BundleQueue {
 public:
  explicit BundleQueue(std::size_t capacity) : capacity_(capacity) {}
  // Returns false when the consumer gave up (the bundle is dropped).
  bool push(std::unique_ptr<Bundle> b) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return queue_.size() < capacity_ || closed_; });
    if (closed_) return false;
    queue_.push_back(std::move(b));
    not_empty_.notify_one();
    return true;
  }
  // nullptr marks the end.
  std::unique_ptr<Bundle> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return !queue_.empty(); });
    std::unique_ptr<Bundle> b = std::move(queue_.front());
    queue_.pop_front();
    not_full_.notify_one();
    return b;
  }
  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    not_full_.notify_all();
  }

 private:
  std::size_t capacity_;
  std::deque<std::unique_ptr<Bundle>> queue_;
  bool closed_ = false;
  std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
};

}  // namespace

ScenarioBagSummary writeScenarioBag(const sim::Scenario& s, const std::string& path,
                                    const ProgressCallback& progress,
                                    const ScenarioBagOptions& options) {
  sim::ScenarioWorld world(s);
  const std::vector<std::int64_t> camera_ns = sim::frameTimesNs(s.camera.rate, s.duration);
  const std::vector<std::int64_t> lidar_ns = sim::frameTimesNs(s.lidar.rate, s.duration);
  std::vector<std::int64_t> all_ns;
  std::set_union(camera_ns.begin(), camera_ns.end(), lidar_ns.begin(), lidar_ns.end(),
                 std::back_inserter(all_ns));
  const std::int64_t start_ns = std::llround(s.start_time * 1e9);
  auto stampOf = [&](std::int64_t t_ns) {
    ::ros::Time stamp;
    stamp.fromNSec(static_cast<std::uint64_t>(start_ns + t_ns));
    return stamp;
  };

  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  if (options.lz4) bag.setCompression(rosbag::compression::LZ4);

  ScenarioBagSummary summary;
  summary.stamps = all_ns.size();
  if (all_ns.empty()) {
    bag.close();
    return summary;
  }
  {
    const ::ros::Time t0 = stampOf(all_ns.front());
    tf2_msgs::TFMessage tf_static;
    tf_static.transforms.push_back(
        transform(t0, frames::kBase, frames::kCamera, s.camera.T_base_camera));
    tf_static.transforms.push_back(
        transform(t0, frames::kBase, frames::kLidar, s.lidar.T_base_lidar));
    bag.write(topics::kTfStatic, t0, tf_static, latched(tf_static, "/simulate"));
    // The odometry prior's map -> odom goes on its own topic, not on /tf: on replay the tracker
    // publishes the corrected map -> odom, and two publishers of one transform fight.
    const geometry_msgs::TransformStamped prior =
        transform(t0, frames::kMap, frames::kOdom, world.mapToOdom());
    bag.write(topics::kMapOdomPrior, t0, prior, latched(prior, "/simulate"));
  }

  // Simulation runs one stamp ahead of the bag writing, in its own thread (ray casting itself
  // uses all cores); frames are still made one after the other, in time order.
  const PinholeModel& cam = s.camera.model;
  const SensorRays& lidar_rays = world.lidarRays();
  BundleQueue queue(3);
  std::exception_ptr failure;
  std::thread simulator([&] {
    try {
      std::size_t ci = 0, li = 0;
      for (const std::int64_t t_ns : all_ns) {
        auto b = std::make_unique<Bundle>();
        const double t = static_cast<double>(t_ns) * 1e-9;
        const ::ros::Time stamp = b->stamp = stampOf(t_ns);
        b->tf.transforms.push_back(
            transform(stamp, frames::kOdom, frames::kBase, world.odometry(t)));
        b->base.header = header(stamp, frames::kMap);
        b->base.pose = toPose(world.basePose(t));

        if (ci < camera_ns.size() && camera_ns[ci] == t_ns) {
          sim::CameraFrame f = world.renderCamera(t, ci);
          std_msgs::Header h = header(stamp, frames::kCamera);
          h.seq = static_cast<std::uint32_t>(ci);  // numbered as a driver's publisher numbers them
          b->camera = true;
          b->info = toCameraInfo(cam);
          b->info.header = h;
          b->rgb = image(h, cam.width, cam.height, sensor_msgs::image_encodings::RGB8, 3,
                         std::move(f.rgb));
          b->depth = depthToImage(f.depth, cam.width, cam.height);
          b->depth.header = h;
          b->depth_labels = image(h, cam.width, cam.height, sensor_msgs::image_encodings::MONO8, 1,
                                  std::move(f.labels));
          b->truth.header = header(stamp, frames::kMap);
          for (std::size_t i = 0; i < s.objects.size(); ++i) {
            scene_graph_tracker::ObjectPose o;
            o.id = s.objects[i].id;
            o.class_name = s.objects[i].class_name;
            o.pose = toPose(f.T_map_objects[i]);
            b->truth.objects.push_back(std::move(o));
          }
          b->hypotheses.header = h;
          for (const sim::Hypothesis& d : world.detect(f, ci)) {
            scene_graph_tracker::PoseHypothesis p;
            p.class_name = d.class_name;
            p.pose = toPose(d.T_camera_object);
            p.score = d.score;
            b->hypotheses.hypotheses.push_back(std::move(p));
          }
          ++ci;
        }
        if (li < lidar_ns.size() && lidar_ns[li] == t_ns) {
          sim::LidarFrame f = world.scanLidar(t, li);
          b->lidar = true;
          b->cloud = cloudFromRanges(f.range, lidar_rays, f.intensity);
          b->cloud.header = header(stamp, frames::kLidar);
          b->cloud.header.seq = static_cast<std::uint32_t>(li);
          b->lidar_labels =
              image(header(stamp, frames::kLidar), lidar_rays.width, lidar_rays.height,
                    sensor_msgs::image_encodings::MONO8, 1, std::move(f.labels));
          ++li;
        }
        if (!queue.push(std::move(b))) return;  // the writer failed
      }
    } catch (...) {
      failure = std::current_exception();
    }
    queue.push(nullptr);
  });

  try {
    std::size_t done = 0;
    while (std::unique_ptr<Bundle> b = queue.pop()) {
      const ::ros::Time& stamp = b->stamp;
      bag.write(topics::kTf, stamp, b->tf);
      bag.write(topics::kGtBasePose, stamp, b->base);
      if (b->camera) {
        bag.write(topics::kRgb, stamp, b->rgb);
        bag.write(topics::kRgbInfo, stamp, b->info);
        bag.write(topics::kDepth, stamp, b->depth);
        bag.write(topics::kDepthInfo, stamp, b->info);
        bag.write(topics::kGtDepthLabels, stamp, b->depth_labels);
        bag.write(topics::kGtObjects, stamp, b->truth);
        bag.write(topics::kHypotheses, stamp, b->hypotheses);
        ++summary.camera_frames;
        summary.hypotheses += b->hypotheses.hypotheses.size();
      }
      if (b->lidar) {
        bag.write(topics::kVelodyne, stamp, b->cloud);
        bag.write(topics::kGtVelodyneLabels, stamp, b->lidar_labels);
        ++summary.lidar_scans;
      }
      if (progress) progress(++done, all_ns.size());
    }
  } catch (...) {
    queue.close();
    simulator.join();
    throw;
  }
  simulator.join();
  if (failure) std::rethrow_exception(failure);
  bag.close();
  return summary;
}

}  // namespace sgt::ros
