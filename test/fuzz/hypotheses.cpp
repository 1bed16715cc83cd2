// Pose hypotheses into the pipeline: PoseHypothesisArray messages (class names, scores and poses
// from the bytes: mostly near the one object in view, sometimes NaN, infinite or huge) through
// the tracker nodelet's conversion (FrameAssembler: hypotheses closest in time to the depth
// image, moved into the base frame) into FramePipeline::process, over one to three frames of a
// small scene: a 64 x 48 depth camera looking at a box on a table, a catalog of a box and a
// cylinder.
#include <scene_graph_tracker/PoseHypothesisArray.h>

#include <boost/make_shared.hpp>

#include "fuzz_common.hpp"
#include "fuzz_targets.hpp"
#include "scene_graph_tracker/geometry/primitives.hpp"
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/ros/conversions.hpp"
#include "scene_graph_tracker/ros/frame_assembler.hpp"
#include "scene_graph_tracker/simulation/sensor_simulation.hpp"

namespace {

using sgt::fuzz::name;
using sgt::fuzz::number;

// What tf2 would throw for a frame it does not know.
struct LookupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Eigen::Isometry3d translated(double x, double y, double z, double yaw = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(x, y, z));
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

// The scene, built once: the robot's base at the map origin (odometry exact), the camera 1.2 m
// up looking at a table 1 m ahead with the box on it.
struct Scene {
  std::shared_ptr<sgt::ObjectCatalog> catalog = std::make_shared<sgt::ObjectCatalog>();
  std::shared_ptr<sgt::TriangleMesh> map = std::make_shared<sgt::TriangleMesh>();
  Eigen::Isometry3d T_base_camera, T_map_box;
  sensor_msgs::CameraInfo info;
  sensor_msgs::Image depth;

  Scene() {
    const auto add = [&](const std::string& class_name, sgt::TriangleMesh mesh,
                         sgt::Symmetry symmetry) {
      sgt::ObjectClass c;
      c.name = class_name;
      c.mesh_path = "(generated)";
      auto m = std::make_shared<const sgt::TriangleMesh>(std::move(mesh));
      c.box = m->boundingBox(), c.diameter = m->diameter(), c.mesh = m;
      c.symmetry = std::move(symmetry);
      catalog->add(std::move(c));
    };
    add("box", sgt::makeBox(Eigen::Vector3f(0.2f, 0.15f, 0.1f)), {});
    sgt::Symmetry about_z;
    about_z.continuous.push_back({});
    add("cylinder", sgt::makeCylinder(0.05f, 0.2f, 16), about_z);
    map->append(sgt::makeBox(Eigen::Vector3f(4.0f, 4.0f, 0.02f)),
                translated(0, 0, -0.01).cast<float>());
    map->append(sgt::makeBox(Eigen::Vector3f(0.8f, 0.6f, 0.7f)),
                translated(1.0, 0, 0.35).cast<float>());
    T_map_box = translated(1.0, 0.0, 0.75, 0.3);
    T_base_camera = sgt::opticalLookAt(Eigen::Vector3d(0, 0, 1.2), Eigen::Vector3d(1.0, 0, 0.7));

    sgt::PinholeModel cam;
    cam.width = 64, cam.height = 48, cam.fx = cam.fy = 50.0, cam.cx = 31.5, cam.cy = 23.5;
    sgt::RaycastScene world;
    world.setStaticMap(map, 1);
    world.addInstance(10, world.addMesh(catalog->get("box").mesh), T_map_box);
    world.commit();
    const sgt::SensorRays rays = sgt::makeRays(cam);
    depth = sgt::ros::depthToImage(sgt::depthImage(sgt::simulate(world, rays, T_base_camera), rays),
                                   cam.width, cam.height);
    depth.header.frame_id = "camera";
    info = sgt::ros::toCameraInfo(cam);
    info.header.frame_id = "camera";
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

// base_link, odom and the camera as the scene has them; "detector" is a frame at the base; any
// other frame is unknown.
Eigen::Isometry3d frameInBase(const std::string& frame) {
  if (frame == "base_link" || frame == "odom" || frame == "detector")
    return Eigen::Isometry3d::Identity();
  if (frame == "camera") return scene().T_base_camera;
  throw LookupError("frame '" + frame + "' does not exist");
}

geometry_msgs::Pose hypothesisPose(FuzzedDataProvider& p, const std::string& frame) {
  geometry_msgs::Pose pose;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (frame == "camera") t = (scene().T_base_camera.inverse() * scene().T_map_box).translation();
  if (frame == "detector") t = scene().T_map_box.translation();
  if (p.ConsumeIntegralInRange<int>(0, 3) != 0) {  // near the box
    pose.position.x = t.x() + p.ConsumeFloatingPointInRange(-0.3, 0.3);
    pose.position.y = t.y() + p.ConsumeFloatingPointInRange(-0.3, 0.3);
    pose.position.z = t.z() + p.ConsumeFloatingPointInRange(-0.3, 0.3);
  } else {
    pose.position.x = number(p, 1e3), pose.position.y = number(p, 1e3);
    pose.position.z = number(p, 1e3);
  }
  const bool sane = p.ConsumeIntegralInRange<int>(0, 3) != 0;
  pose.orientation.w = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  pose.orientation.x = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  pose.orientation.y = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  pose.orientation.z = sane ? p.ConsumeFloatingPointInRange(-1.0, 1.0) : number(p, 1.0);
  return pose;
}

scene_graph_tracker::PoseHypothesisArray::Ptr hypotheses(FuzzedDataProvider& p,
                                                         const ::ros::Time& stamp) {
  auto msg = boost::make_shared<scene_graph_tracker::PoseHypothesisArray>();
  msg->header.stamp = stamp;
  if (p.ConsumeIntegralInRange<int>(0, 7) == 0)  // sometimes too old or too new
    msg->header.stamp += ::ros::Duration(p.ConsumeFloatingPointInRange(-0.3, 0.3));
  msg->header.frame_id = name(p, {"camera", "camera", "detector", "nowhere"});
  const int n = p.ConsumeIntegralInRange<int>(0, 6);
  for (int k = 0; k < n; ++k) {
    scene_graph_tracker::PoseHypothesis h;
    h.class_name = name(p, {"box", "box", "cylinder", "unknown", ""});
    h.pose = hypothesisPose(p, msg->header.frame_id);
    h.score = p.ConsumeIntegralInRange<int>(0, 3) != 0 ? p.ConsumeFloatingPointInRange(0.0f, 1.0f)
                                                       : static_cast<float>(number(p, 1.0));
    msg->hypotheses.push_back(std::move(h));
  }
  return msg;
}

sgt::PipelineOptions pipelineOptions(FuzzedDataProvider& p) {
  sgt::PipelineOptions o;
  // Quick confirmation, so that confirmed tracks (relations, orientation search) are reached.
  o.confirm_hits = p.ConsumeIntegralInRange<int>(1, 3);
  o.confirm_detections = p.ConsumeIntegralInRange<int>(1, 3);
  o.search_orientations = p.ConsumeBool();
  o.localize = p.ConsumeBool();
  o.localize_with_lidar_only = p.ConsumeBool();
  return o;
}

}  // namespace

int sgtFuzzHypotheses(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  const Scene& s = scene();
  sgt::FramePipeline pipeline(s.catalog, s.map, pipelineOptions(p));
  sgt::ros::FrameAssemblerOptions options;
  options.lidar.columns = 16, options.lidar.rings = 2;  // no scans here: few rays to make
  sgt::ros::FrameAssembler assembler(
      options, [](const std::string& target, const std::string& source, const ::ros::Time&) {
        return frameInBase(target).inverse() * frameInBase(source);
      });
  const int frames = p.ConsumeIntegralInRange<int>(1, 3);
  const double dt = p.ConsumeFloatingPointInRange(0.02, 1.0);
  for (int f = 0; f < frames; ++f) {
    const ::ros::Time stamp(100.0 + f * dt);
    assembler.addHypotheses(hypotheses(p, stamp));
    sensor_msgs::Image depth = s.depth;
    depth.header.stamp = stamp;
    sgt::ros::AssembledFrame frame;
    try {
      frame = assembler.assemble(depth, s.info);
    } catch (const LookupError&) {  // the hypotheses' frame is unknown: no frame
      continue;
    }
    const std::size_t hypotheses = frame.frame.hypotheses.size();
    const sgt::PipelineResult r = pipeline.process(std::move(frame.frame));
    if (sgt::fuzz::verbose()) {
      std::fprintf(stderr, "frame %d: %zu hypotheses, %zu warnings, tracks:", f, hypotheses,
                   frame.warnings.size());
      for (const sgt::TrackedObject& o : r.objects)
        std::fprintf(stderr, " %s (%s, %d inliers)", o.id.c_str(), sgt::toString(o.state),
                     o.quality.inliers);
      std::fprintf(stderr, "\n");
    }
    for (const sgt::TrackedObject& o : r.objects)
      sgt::fuzz::expect(o.T_map_object.matrix().allFinite() && o.covariance.allFinite(),
                        "tracked objects with finite poses and covariances");
  }
  return 0;
}

SGT_FUZZ_ENTRY(sgtFuzzHypotheses)
