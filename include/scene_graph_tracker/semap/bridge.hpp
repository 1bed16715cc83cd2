// semap_bridge: stores the tracker's scene graph in the SEMAP database (PostgreSQL + PostGIS +
// SFCGAL) and answers spatial queries from it.
//
// Subscribes: scene_graph (SceneGraph; world poses by composing each node's parent chain), or
// tracked_objects (TrackedObjectArray, poses in the header frame) with ~source: tracked_objects.
// Writes: object classes (box, hull), instances, pose history, relation intervals, through a
// bounded queue in a writer thread (semap/writer.hpp): the node keeps running while the
// database is down and writes the backlog when it is back.
// Services (answered by SQL on the database; success false + message when it is unreachable):
//   ~query_relations, ~objects_on, ~objects_in, ~directional_relations, ~where_was, ~relation_since
// The map's furniture (~furniture, relations/furniture.hpp) is stored as fixed instances, so
// "what is on table_2" is answered; ~directional_relations takes a viewer frame (TF) too.
// A fleet shares one database: each robot's bridge has its own ~robot_id (forRobot).
// Parameters: config/semap.yaml.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <scene_graph_tracker/DirectionalRelations.h>
#include <scene_graph_tracker/ObjectsIn.h>
#include <scene_graph_tracker/ObjectsOn.h>
#include <scene_graph_tracker/QueryRelations.h>
#include <scene_graph_tracker/RelationSince.h>
#include <scene_graph_tracker/SceneGraph.h>
#include <scene_graph_tracker/TrackedObjectArray.h>
#include <scene_graph_tracker/WhereWas.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <functional>
#include <map>
#include <memory>
#include <mutex>

#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/semap/writer.hpp"

namespace sgt::ros {

// The class's box and up to `max_points` of its mesh vertices (spread over the vertex list).
semap::ClassShape classShape(const ObjectClass& c, std::size_t max_points = 200);

// Node id -> pose in the scene graph's root frame: T_parent_node composed along parents; a parent
// that is not a node is the root. Throws ConversionError on a parent cycle.
std::map<std::string, Eigen::Isometry3d> worldPoses(const scene_graph_tracker::SceneGraph& graph);

// A class name -> its shape, or nullptr when the class is unknown (its objects are not stored).
using ShapeLookup = std::function<std::shared_ptr<const semap::ClassShape>(const std::string&)>;

// The rows one message stands for: every object of a known class at its world pose, stamped
// `stamp`. Throws ConversionError on a malformed message (non-finite or zero-quaternion pose,
// empty or duplicate id, parent cycle, more than kMaxFrameObjects objects, a name that is not
// UTF-8, holds a NUL or is longer than kMaxNameBytes): nothing of it is stored.
constexpr std::size_t kMaxFrameObjects = 10000;
constexpr std::size_t kMaxNameBytes = 256;
semap::Frame frameFromSceneGraph(const scene_graph_tracker::SceneGraph& graph, double stamp,
                                 const ShapeLookup& shape);
semap::Frame frameFromTrackedObjects(const scene_graph_tracker::TrackedObjectArray& objects,
                                     double stamp, const ShapeLookup& shape);

// The frame as robot `robot` stores it in a database several robots share: its ids (and parents
// that are ids of the frame) as '<robot>/<id>', and frame.robot set. An empty robot leaves the
// frame as it is. Throws ConversionError for a robot id that is not a valid name or holds '/'.
semap::Frame forRobot(semap::Frame frame, const std::string& robot);

// What became of the messages. Every message in is throttled (~write_period), malformed or
// pushed to the writer; missed counts messages that never arrived (header.seq gaps).
struct BridgeCounts {
  std::size_t messages_in = 0, missed = 0, malformed = 0, throttled = 0;
  semap::WriterStats writer;
};

class SemapBridge {
 public:
  SemapBridge(::ros::NodeHandle nh, ::ros::NodeHandle pnh);
  ~SemapBridge();
  semap::WriterStats writerStats() const { return writer_->stats(); }
  BridgeCounts counts() const;

 private:
  void onSceneGraph(const scene_graph_tracker::SceneGraphConstPtr& msg);
  void onTrackedObjects(const scene_graph_tracker::TrackedObjectArrayConstPtr& msg);
  void accept(const std_msgs::Header& header,
              const std::function<semap::Frame(const ShapeLookup&)>& convert);
  void countSequence(std::uint32_t seq);
  void publishDiagnostics();
  void push(semap::Frame frame);
  std::shared_ptr<const semap::ClassShape> shape(const std::string& class_name);

  // Runs f on the query connection (connecting when needed); fills success and message.
  template <class Response, class F>
  bool answer(Response& res, F f);
  bool onQueryRelations(scene_graph_tracker::QueryRelations::Request& req,
                        scene_graph_tracker::QueryRelations::Response& res);
  bool onObjectsOn(scene_graph_tracker::ObjectsOn::Request& req,
                   scene_graph_tracker::ObjectsOn::Response& res);
  bool onObjectsIn(scene_graph_tracker::ObjectsIn::Request& req,
                   scene_graph_tracker::ObjectsIn::Response& res);
  bool onDirectional(scene_graph_tracker::DirectionalRelations::Request& req,
                     scene_graph_tracker::DirectionalRelations::Response& res);
  bool onWhereWas(scene_graph_tracker::WhereWas::Request& req,
                  scene_graph_tracker::WhereWas::Response& res);
  bool onRelationSince(scene_graph_tracker::RelationSince::Request& req,
                       scene_graph_tracker::RelationSince::Response& res);

  semap::DbSettings settings_;
  ObjectCatalog catalog_;
  std::map<std::string, std::shared_ptr<const semap::ClassShape>> shapes_;
  std::unique_ptr<semap::SemapWriter> writer_;
  double write_period_ = 0.0, relation_period_ = 0.5;
  std::optional<double> last_write_, last_relations_;
  mutable std::mutex counts_mutex_;
  BridgeCounts counts_;  // writer stats filled in by counts()
  std::uint32_t last_seq_ = 0;

  std::mutex query_mutex_;
  std::unique_ptr<semap::SemapDb> query_db_;

  std::string robot_id_;  // several robots in one database: prefixes the ids (forRobot)
  std::string map_frame_ =
      "map";  // the frame of the stored poses (viewer frames are looked up in it)
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_{tf_buffer_};

  ::ros::Subscriber sub_;
  ::ros::CallbackQueue service_queue_;
  ::ros::AsyncSpinner service_spinner_;
  std::vector<::ros::ServiceServer> services_;
  ::ros::Publisher diagnostics_pub_;
  ::ros::WallTimer diagnostics_timer_;
};

}  // namespace sgt::ros
