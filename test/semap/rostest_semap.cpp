// rostest: the semap_bridge node on live topics. The test starts its own PostgreSQL server and the
// node (pointed at that server's port), publishes scene graphs (a relay on a KLT, a screwdriver
// beside it), and calls every service; the answers must equal the C++ relation engine's on the
// same boxes. Then the server is stopped: queries fail with a message, the node keeps running and
// writes what arrived meanwhile once the server is back.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <scene_graph_tracker/DirectionalRelations.h>
#include <scene_graph_tracker/ObjectsIn.h>
#include <scene_graph_tracker/ObjectsOn.h>
#include <scene_graph_tracker/QueryRelations.h>
#include <scene_graph_tracker/RelationSince.h>
#include <scene_graph_tracker/SceneGraph.h>
#include <scene_graph_tracker/WhereWas.h>
#include <signal.h>
#include <sys/wait.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <cstdio>
#include <functional>
#include <set>
#include <tuple>

#include "pg_server.hpp"
#include "scene_graph_tracker/relations/furniture.hpp"
#include "scene_graph_tracker/relations/spatial_relations.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/semap/bridge.hpp"

namespace sgt {
namespace {

using Triple = std::tuple<std::string, std::string, std::string>;

Eigen::Isometry3d at(const Eigen::Vector3d& t, double yaw = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t,
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

class SemapBridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SGT_REQUIRE_POSTGRES();
    pg_ = std::make_unique<test::PgServer>();
    catalog_ = loadObjectCatalog("package://scene_graph_tracker/config/objects.yaml");
    const std::string port = "_db_port:=" + std::to_string(pg_->port()),
                      passfile = "_db_passfile:=" + pg_->settings().passfile;
    std::vector<std::string> args = {"__name:=semap_bridge", port, passfile};
    args.insert(args.end(), extra_args_.begin(), extra_args_.end());
    node_ = startNode(args);
    ASSERT_GT(node_, 0);
    graph_pub_ = nh_.advertise<scene_graph_tracker::SceneGraph>("/scene_graph", 10);
    ASSERT_TRUE(
        ::ros::service::waitForService("/semap_bridge/relation_since", ::ros::Duration(60.0)))
        << "the semap_bridge node did not come up";
    for (int i = 0; i < 100 && graph_pub_.getNumSubscribers() == 0; ++i)
      ::ros::Duration(0.05).sleep();
  }
  void TearDown() override {
    for (pid_t pid : {node_, second_node_})
      if (pid > 0) {
        kill(pid, SIGINT);
        waitpid(pid, nullptr, 0);
      }
    // `_name:=value` arguments stay on the parameter server: the next test's node must not
    // inherit this one's furniture or robot id.
    for (const char* ns : {"/semap_bridge", "/semap_bridge_b"}) ::ros::param::del(ns);
  }

  // A semap_bridge process with these arguments (and fast writing and reconnection); its pid.
  static pid_t startNode(std::vector<std::string> args) {
    args.insert(args.begin(), SGT_SEMAP_BRIDGE_NODE);
    for (const char* a : {"_write_period:=0.0", "_relation_period:=0.0", "_backoff_max:=0.3"})
      args.push_back(a);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      execv(SGT_SEMAP_BRIDGE_NODE, argv.data());
      _exit(127);
    }
    return pid;
  }

  // The relay's pose on the KLT (box bottom 5 mm above the KLT's top), or away on the floor.
  Eigen::Isometry3d relayOnKlt(bool on) const {
    const auto& klt = catalog_.get("klt").box;
    const auto& relay = catalog_.get("relay").box;
    if (!on) return at(Eigen::Vector3d(1.0, 0.0, -relay.min().z()));
    return at(Eigen::Vector3d(-relay.center().x() + 0.03, -relay.center().y(),
                              klt.max().z() + 0.005 - relay.min().z()),
              0.3);
  }

  // klt_1 at the origin, relay_1 as the KLT's child, screwdriver_1 beside the KLT (+y: its left).
  void publish(double stamp, bool relay_on) {
    scene_graph_tracker::SceneGraph g;
    g.header.stamp = ::ros::Time(stamp), g.header.frame_id = "map";
    auto node = [&](const std::string& id, const std::string& cls, const std::string& parent,
                    const Eigen::Isometry3d& T) {
      scene_graph_tracker::SceneGraphNode n;
      n.id = id, n.class_name = cls, n.parent = parent, n.T_parent_node = ros::toTransform(T);
      g.nodes.push_back(n);
    };
    node("klt_1", "klt", "map", T_klt_);
    node("relay_1", "relay", "klt_1", relayOnKlt(relay_on));  // relative to the KLT
    node("screwdriver_1", "screwdriver", "map", T_screwdriver_);
    graph_pub_.publish(g);
  }

  // Until where_was(id, stamp) finds a pose stored at `stamp`; `republish` (if given) every 0.5 s
  // meanwhile (a message sent before the subscription is connected is lost).
  bool waitStored(const std::string& id, double stamp, const std::function<void()>& republish = {},
                  double timeout = 30.0) {
    scene_graph_tracker::WhereWas w;
    w.request.id = id, w.request.stamp = ::ros::Time(stamp);
    int round = 0;
    for (const auto end = ::ros::WallTime::now() + ::ros::WallDuration(timeout);
         ::ros::WallTime::now() < end; ++round) {
      if (::ros::service::call("/semap_bridge/where_was", w) && w.response.found &&
          std::abs(w.response.pose_stamp.toSec() - stamp) < 1e-3)
        return true;
      if (republish && round % 10 == 9) republish();
      ::ros::WallDuration(0.05).sleep();
    }
    return false;
  }
  // `prefix`: the bridge's robot id and '/' when it has one.
  bool publishStored(double stamp, bool relay_on, const std::string& prefix = "") {
    publish(stamp, relay_on);
    return waitStored(prefix + "relay_1", stamp, [=] { publish(stamp, relay_on); });
  }

  // The engine's relations among the three boxes (world poses as published).
  std::set<Triple> coreRelations(relations::Mode mode, bool relay_on) const {
    const std::vector<std::pair<std::string, relations::OrientedBox>> boxes = {
        {"klt_1", relations::orientedBox(catalog_.get("klt").box.cast<double>(), T_klt_)},
        {"relay_1", relations::orientedBox(catalog_.get("relay").box.cast<double>(),
                                           T_klt_ * relayOnKlt(relay_on))},
        {"screwdriver_1",
         relations::orientedBox(catalog_.get("screwdriver").box.cast<double>(), T_screwdriver_)}};
    std::set<Triple> out;
    for (const auto& [t, tb] : boxes)
      for (const auto& [r, rb] : boxes)
        for (int k = 0; k < relations::kRelationCount && t != r; ++k)
          if (relations::holds(static_cast<relations::Relation>(k), mode, tb, rb))
            out.insert({t, relations::relationName(static_cast<relations::Relation>(k)), r});
    return out;
  }

  std::set<Triple> queried(const std::string& mode) {
    scene_graph_tracker::QueryRelations q;
    q.request.mode = mode;
    EXPECT_TRUE(::ros::service::call("/semap_bridge/query_relations", q));
    EXPECT_TRUE(q.response.success) << q.response.message;
    std::set<Triple> out;
    for (const auto& r : q.response.relations) out.insert({r.subject, r.relation, r.object});
    return out;
  }

  std::vector<std::string> extra_args_;  // more node arguments, set before SetUp
  ::ros::NodeHandle nh_;
  ::ros::Publisher graph_pub_;
  std::unique_ptr<test::PgServer> pg_;
  ObjectCatalog catalog_;
  pid_t node_ = -1, second_node_ = -1;
  const Eigen::Isometry3d T_klt_ = at(Eigen::Vector3d(0.5, 0.2, 0.8), 0.4);
  const Eigen::Isometry3d T_screwdriver_ = T_klt_ * at(Eigen::Vector3d(0.0, 0.3, 0.0));
};

TEST_F(SemapBridgeTest, ServicesAnswerFromTheDatabase) {
  ASSERT_TRUE(publishStored(100.0, true)) << "the scene graph did not reach the database";

  const auto strict = queried("strict");
  EXPECT_EQ(strict, coreRelations(relations::Mode::Strict, true));
  EXPECT_TRUE(strict.count({"relay_1", "on", "klt_1"}));
  EXPECT_TRUE(strict.count({"screwdriver_1", "left_of", "klt_1"}));
  EXPECT_EQ(queried("relaxed"), coreRelations(relations::Mode::Relaxed, true));

  scene_graph_tracker::ObjectsOn on;
  on.request.reference = "klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/objects_on", on));
  EXPECT_EQ(on.response.ids, std::vector<std::string>{"relay_1"});
  scene_graph_tracker::ObjectsIn in;
  in.request.reference = "klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/objects_in", in));
  EXPECT_TRUE(in.response.success);
  EXPECT_TRUE(in.response.ids.empty());
  scene_graph_tracker::DirectionalRelations dir;
  dir.request.a = "screwdriver_1", dir.request.b = "klt_1", dir.request.mode = "strict";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/directional_relations", dir));
  EXPECT_EQ(dir.response.relations, std::vector<std::string>{"left_of"});

  ASSERT_TRUE(publishStored(101.0, false));  // the relay taken off the KLT
  scene_graph_tracker::RelationSince since;
  since.request.subject = "relay_1", since.request.relation = "on", since.request.object = "klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/relation_since", since));
  EXPECT_TRUE(since.response.success);
  EXPECT_FALSE(since.response.holds);
  ASSERT_TRUE(publishStored(102.0, true));  // and put back
  ASSERT_TRUE(::ros::service::call("/semap_bridge/relation_since", since));
  EXPECT_TRUE(since.response.holds);
  EXPECT_TRUE(since.response.since_known);
  EXPECT_NEAR(since.response.since.toSec(), 102.0, 1e-3);

  scene_graph_tracker::WhereWas w;
  w.request.id = "relay_1", w.request.stamp = ::ros::Time(101.5);
  ASSERT_TRUE(::ros::service::call("/semap_bridge/where_was", w));
  ASSERT_TRUE(w.response.found);
  EXPECT_NEAR(w.response.pose_stamp.toSec(), 101.0, 1e-3);
  EXPECT_EQ(w.response.parent, "klt_1");
  const Eigen::Isometry3d T_world_relay = T_klt_ * relayOnKlt(false);  // stored in the root frame
  EXPECT_LT((ros::toEigen(w.response.pose).translation() - T_world_relay.translation()).norm(),
            1e-6);
  w.request.stamp = ::ros::Time(99.0);
  ASSERT_TRUE(::ros::service::call("/semap_bridge/where_was", w));
  EXPECT_TRUE(w.response.success);
  EXPECT_FALSE(w.response.found);

  scene_graph_tracker::QueryRelations bad;
  bad.request.mode = "fuzzy";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/query_relations", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_NE(bad.response.message.find("strict"), std::string::npos) << bad.response.message;
}

TEST_F(SemapBridgeTest, KeepsRunningWhileTheDatabaseIsDown) {
  ASSERT_TRUE(publishStored(200.0, true));
  pg_->stop();
  scene_graph_tracker::ObjectsOn on;
  on.request.reference = "klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/objects_on", on))
      << "the node should answer, not die";
  EXPECT_FALSE(on.response.success);
  EXPECT_NE(on.response.message.find("semap database"), std::string::npos) << on.response.message;
  for (int i = 1; i <= 5; ++i) {  // while it is down
    publish(200.0 + i, i % 2 == 0);
    ::ros::WallDuration(0.1).sleep();
  }
  pg_->start();
  for (int i = 1; i <= 5; ++i)
    EXPECT_TRUE(waitStored("relay_1", 200.0 + i)) << "frame " << i << " lost";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/objects_on", on));
  EXPECT_TRUE(on.response.success) << on.response.message;
  EXPECT_TRUE(on.response.ids.empty());  // the last frame (205) has the relay on the floor
}

// The bridge's diagnostics: the latest values of its counters, by key.
std::map<std::string, double> bridgeCounters(::ros::NodeHandle& nh, double timeout = 5.0) {
  std::map<std::string, double> out;
  const auto msg = ::ros::topic::waitForMessage<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", nh, ::ros::Duration(timeout));
  if (!msg) return out;
  for (const auto& s : msg->status)
    if (s.name == "scene_graph_tracker: semap_bridge")
      for (const auto& kv : s.values) out[kv.key] = std::stod(kv.value);
  return out;
}

TEST_F(SemapBridgeTest, MalformedMessagesAreCountedAndTheNodeKeepsStoring) {
  ASSERT_TRUE(publishStored(300.0, true));
  scene_graph_tracker::SceneGraph bad;
  bad.header.stamp = ::ros::Time(301.0);
  bad.nodes.resize(1);
  bad.nodes[0].id = "klt_1", bad.nodes[0].class_name = "klt";  // zero quaternion
  graph_pub_.publish(bad);
  bad.nodes[0].T_parent_node.rotation.w = 1.0;
  bad.nodes[0].T_parent_node.translation.x = std::nan("");
  graph_pub_.publish(bad);
  bad.nodes[0].T_parent_node.translation.x = 0.0;
  bad.nodes.push_back(bad.nodes[0]);  // the same id twice
  graph_pub_.publish(bad);
  ASSERT_TRUE(publishStored(302.0, false)) << "the node should keep storing";
  std::map<std::string, double> c;
  for (int i = 0; i < 20 && c["messages_malformed"] < 3; ++i) c = bridgeCounters(nh_);
  EXPECT_EQ(c["messages_malformed"], 3);
  EXPECT_EQ(c["pushed"], c["written"] + c["dropped"] + c["rejected"] + c["pending"]);
  EXPECT_EQ(c["messages_in"], c["messages_malformed"] + c["throttled"] + c["pushed"]);
  EXPECT_GE(c["written"], 2);
}

TEST_F(SemapBridgeTest, HostileNamesRoundTripAndOversizedOnesAreRefused) {
  ASSERT_TRUE(publishStored(400.0, true));
  const std::vector<std::string> names = {"'; DROP TABLE instance;--", "Robert'); --",
                                          "\xe3\x83\xac\xe3\x83\xbc_1 \xf0\x9f\xa4\x96",
                                          std::string(ros::kMaxNameBytes, 'n')};
  scene_graph_tracker::SceneGraph g;
  g.header.stamp = ::ros::Time(401.0), g.header.frame_id = "map";
  for (std::size_t k = 0; k < names.size(); ++k) {
    scene_graph_tracker::SceneGraphNode n;
    n.id = names[k], n.class_name = "relay", n.parent = "map";
    n.T_parent_node = ros::toTransform(at(Eigen::Vector3d(k, 3, 0)));
    g.nodes.push_back(n);
  }
  graph_pub_.publish(g);
  for (std::size_t k = 0; k < names.size(); ++k) {
    ASSERT_TRUE(waitStored(names[k], 401.0, [&] { graph_pub_.publish(g); })) << names[k];
    scene_graph_tracker::WhereWas w;
    w.request.id = names[k], w.request.stamp = ::ros::Time(401.0);
    ASSERT_TRUE(::ros::service::call("/semap_bridge/where_was", w));
    EXPECT_NEAR(w.response.pose.position.x, k, 1e-9) << names[k];
  }
  scene_graph_tracker::QueryRelations q;  // hostile names in a query: answered, nothing dropped
  q.request.subject = names[0], q.request.object = "x' OR '1'='1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/query_relations", q));
  EXPECT_TRUE(q.response.success) << q.response.message;
  EXPECT_TRUE(q.response.relations.empty());
  g.nodes.resize(1);
  g.nodes[0].id = std::string(1 << 20, 'x');  // 1 MB: no index holds it
  g.header.stamp = ::ros::Time(402.0);
  graph_pub_.publish(g);
  ASSERT_TRUE(publishStored(403.0, false)) << "the node should keep storing";
  std::map<std::string, double> c;
  for (int i = 0; i < 20 && c["messages_malformed"] < 1; ++i) c = bridgeCounters(nh_);
  EXPECT_EQ(c["messages_malformed"], 1);
  EXPECT_EQ(c["rejected"], c["duplicate_frames"]) << "the database refused only republished frames";
}

// The bridge with a furniture file: a bench under the KLT, stored as a fixed instance; and
// directional relations seen from two viewer frames on either side of the KLT.
class SemapFurnitureTest : public SemapBridgeTest {
 protected:
  SemapFurnitureTest() {
    // A bench 0.78 m high (its box from the floor), its top 1 mm below the KLT's bottom.
    const auto klt =
        loadObjectCatalog("package://scene_graph_tracker/config/objects.yaml").get("klt").box;
    relations::Entity bench;
    bench.name = "bench_1", bench.movable = false;
    bench.box.half_extents = Eigen::Vector3d(0.8, 0.5, 0.39);
    bench.box.T_world_box = T_klt_ * at(Eigen::Vector3d(0, 0, klt.min().z() - 0.391));
    furniture_ = "/tmp/sgt_rostest_semap_furniture_" + std::to_string(getpid()) + ".yaml";
    relations::saveFurniture({bench}, furniture_);
    extra_args_ = {"_furniture:=" + furniture_};
  }
  ~SemapFurnitureTest() override { std::remove(furniture_.c_str()); }

  std::vector<std::string> seenFrom(const std::string& frame, bool& success) {
    scene_graph_tracker::DirectionalRelations dir;
    dir.request.a = "screwdriver_1", dir.request.b = "klt_1", dir.request.viewer_frame = frame;
    EXPECT_TRUE(::ros::service::call("/semap_bridge/directional_relations", dir));
    success = dir.response.success;
    return dir.response.relations;
  }
  std::string furniture_;
};

TEST_F(SemapFurnitureTest, FurnitureAnswersObjectsOnAndViewersSeeTheirOwnLeft) {
  ASSERT_TRUE(publishStored(500.0, true));
  scene_graph_tracker::ObjectsOn on;
  on.request.reference = "bench_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/objects_on", on));
  EXPECT_TRUE(on.response.success) << on.response.message;
  const std::set<std::string> ids(on.response.ids.begin(), on.response.ids.end());
  EXPECT_TRUE(ids.count("klt_1")) << "the KLT stands on the bench";
  EXPECT_FALSE(ids.count("relay_1")) << "the relay is on the KLT";

  tf2_ros::StaticTransformBroadcaster tf;
  auto viewer = [&](const std::string& name, double x) {  // on the KLT's x axis, 2 m away
    geometry_msgs::TransformStamped t;
    t.header.stamp = ::ros::Time::now(), t.header.frame_id = "map", t.child_frame_id = name;
    t.transform = ros::toTransform(T_klt_ * at(Eigen::Vector3d(x, 0, 0.5)));
    return t;
  };
  tf.sendTransform({viewer("behind_the_klt", -2.0), viewer("facing_the_klt", 2.0)});
  bool success = false;
  // The screwdriver is on the KLT's +y side: the left of a viewer looking along the KLT's +x.
  EXPECT_EQ(seenFrom("behind_the_klt", success), std::vector<std::string>{"left_of"});
  EXPECT_TRUE(success);
  EXPECT_EQ(seenFrom("facing_the_klt", success), std::vector<std::string>{"right_of"});
  EXPECT_TRUE(success);
  EXPECT_TRUE(seenFrom("no_such_frame", success).empty());
  EXPECT_FALSE(success);
}

// A fleet: two robots' bridges write into one database, each with its robot id. Both robots'
// KLTs are stored under their own names; a complete frame of one robot leaves the other's
// objects present; relations and where_was name the robot's objects.
class SemapFleetTest : public SemapBridgeTest {
 protected:
  SemapFleetTest() { extra_args_ = {"_robot_id:=tiago_a"}; }
};

TEST_F(SemapFleetTest, TwoBridgesShareOneDatabase) {
  second_node_ = startNode(
      {"__name:=semap_bridge_b", "_robot_id:=tiago_b", "_db_port:=" + std::to_string(pg_->port()),
       "_db_passfile:=" + pg_->settings().passfile, "scene_graph:=/robot_b/scene_graph"});
  ASSERT_GT(second_node_, 0);
  auto b_pub = nh_.advertise<scene_graph_tracker::SceneGraph>("/robot_b/scene_graph", 10);
  ASSERT_TRUE(
      ::ros::service::waitForService("/semap_bridge_b/relation_since", ::ros::Duration(60.0)));
  ASSERT_TRUE(publishStored(600.0, true, "tiago_a/"));
  // Robot b sees one KLT of its own, elsewhere, and keeps publishing it.
  scene_graph_tracker::SceneGraph g;
  g.header.stamp = ::ros::Time(601.0), g.header.frame_id = "map";
  scene_graph_tracker::SceneGraphNode n;
  n.id = "klt_1", n.class_name = "klt", n.parent = "map";
  n.T_parent_node = ros::toTransform(at(Eigen::Vector3d(5.0, 5.0, 0.8)));
  g.nodes.push_back(n);
  ASSERT_TRUE(waitStored("tiago_b/klt_1", 601.0, [&] { b_pub.publish(g); }));

  scene_graph_tracker::ObjectsOn on;  // robot a's relay is still on robot a's KLT
  on.request.reference = "tiago_a/klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge_b/objects_on", on));
  EXPECT_EQ(on.response.ids, std::vector<std::string>{"tiago_a/relay_1"});
  scene_graph_tracker::WhereWas w;
  w.request.id = "tiago_a/relay_1", w.request.stamp = ::ros::Time(700.0);
  ASSERT_TRUE(::ros::service::call("/semap_bridge/where_was", w));
  ASSERT_TRUE(w.response.found);
  EXPECT_EQ(w.response.parent, "tiago_a/klt_1");
  scene_graph_tracker::QueryRelations q;
  q.request.subject = "tiago_b/klt_1";
  ASSERT_TRUE(::ros::service::call("/semap_bridge/query_relations", q));
  EXPECT_TRUE(q.response.success) << q.response.message;
  EXPECT_TRUE(q.response.relations.empty()) << "5 m from robot a's objects: no relation";
}

}  // namespace
}  // namespace sgt

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rostest_semap");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
