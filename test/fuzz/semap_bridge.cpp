// The SEMAP bridge's messages -> rows (sgt::ros::frameFromSceneGraph, frameFromTrackedObjects):
// a SceneGraph or TrackedObjectArray from the bytes (ids and parents from a small set, so that
// duplicates, self-parents and cycles occur; poses mostly plain, sometimes NaN, infinite, huge or
// a zero quaternion), with a shape lookup that knows the classes klt and box only.
#include <cmath>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/semap/bridge.hpp"

namespace {

using sgt::fuzz::name;
using sgt::fuzz::number;

const std::vector<std::string> kIds = {"a", "b", "c", "klt_1", "box_1", "map", ""};
const std::vector<std::string> kClasses = {"klt", "box", "unknown", ""};

std::shared_ptr<const sgt::semap::ClassShape> shapeOf(const std::string& class_name) {
  static const auto shape = [] {
    auto s = std::make_shared<sgt::semap::ClassShape>();
    s->name = "klt";
    s->box =
        Eigen::AlignedBox3d(Eigen::Vector3d(-0.2, -0.15, 0.0), Eigen::Vector3d(0.2, 0.15, 0.15));
    for (int k = 0; k < 8; ++k)
      s->hull_points.push_back(
          Eigen::Vector3d(k & 1 ? 0.2 : -0.2, k & 2 ? 0.15 : -0.15, k & 4 ? 0.15 : 0.0));
    return std::shared_ptr<const sgt::semap::ClassShape>(s);
  }();
  return class_name == "klt" || class_name == "box" ? shape : nullptr;
}

// Count of objects: mostly a few, rarely just over the bridge's limit.
std::size_t objectCount(FuzzedDataProvider& p) {
  return p.ConsumeIntegralInRange<int>(0, 63) == 0 ? sgt::ros::kMaxFrameObjects + 1
                                                   : p.ConsumeIntegralInRange<std::size_t>(0, 12);
}

template <typename Vector, typename Quaternion>
void fill(FuzzedDataProvider& p, Vector& t, Quaternion& q) {
  const bool sane = p.ConsumeIntegralInRange<int>(0, 3) != 0;
  t.x = sane ? p.ConsumeFloatingPointInRange(-5.0, 5.0) : number(p, 5.0);
  t.y = sane ? p.ConsumeFloatingPointInRange(-5.0, 5.0) : number(p, 5.0);
  t.z = sane ? p.ConsumeFloatingPointInRange(-5.0, 5.0) : number(p, 5.0);
  q.w = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  q.x = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  q.y = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  q.z = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
}

void checkFrame(const sgt::semap::Frame& frame, std::size_t messages_objects, double stamp) {
  sgt::fuzz::expect(frame.objects.size() <= messages_objects, "at most one row per object");
  sgt::fuzz::expect(frame.stamp == stamp || std::isnan(stamp), "the frame at the given stamp");
  for (const auto& o : frame.objects) {
    const bool ok = o.shape && !o.id.empty() && o.T_world_object.matrix().allFinite();
    if (!ok || sgt::fuzz::verbose()) {
      const Eigen::Vector3d t = o.T_world_object.translation();
      std::fprintf(stderr, "row '%s' (%s), parent '%s', at %g %g %g\n", o.id.c_str(),
                   o.shape ? o.shape->name.c_str() : "no shape", o.parent.c_str(), t.x(), t.y(),
                   t.z());
    }
    sgt::fuzz::expect(ok, "rows of known classes, with ids and finite poses");
  }
}

}  // namespace

int sgtFuzzSemapBridge(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  const double stamp = p.ConsumeBool() ? p.ConsumeFloatingPointInRange(0.0, 2e9) : number(p, 1e9);
  if (p.ConsumeBool()) {
    scene_graph_tracker::SceneGraph graph;
    graph.nodes.resize(objectCount(p));
    for (auto& n : graph.nodes) {
      n.id = name(p, kIds);
      n.class_name = name(p, kClasses);
      n.parent = name(p, kIds);
      fill(p, n.T_parent_node.translation, n.T_parent_node.rotation);
    }
    graph.edges.resize(p.ConsumeIntegralInRange<int>(0, 3));
    for (auto& e : graph.edges) {
      e.subject = name(p, kIds), e.object = name(p, kIds);
      e.relation = name(p, {"on", "in", "left_of", "above"});
    }
    try {
      checkFrame(sgt::ros::frameFromSceneGraph(graph, stamp, shapeOf), graph.nodes.size(), stamp);
    } catch (const sgt::ros::ConversionError&) {
    }
  } else {
    scene_graph_tracker::TrackedObjectArray objects;
    objects.objects.resize(objectCount(p));
    for (auto& o : objects.objects) {
      o.id = name(p, kIds);
      o.class_name = name(p, kClasses);
      o.parent = name(p, kIds);
      o.state = p.ConsumeIntegral<std::uint8_t>();
      o.inlier_ratio = static_cast<float>(number(p, 1.0));
      fill(p, o.pose.pose.position, o.pose.pose.orientation);
    }
    try {
      checkFrame(sgt::ros::frameFromTrackedObjects(objects, stamp, shapeOf), objects.objects.size(),
                 stamp);
    } catch (const sgt::ros::ConversionError&) {
    }
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzSemapBridge)
