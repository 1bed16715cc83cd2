// The paper's frame for benchmarks: the ~411,698-triangle generated building, the five paper
// objects on the workbench (the real pbr_objects meshes when ../shared/data/pbr_objects exists,
// stand-ins with the same triangle counts otherwise), a 640x480 camera and a VLP-16 on a robot
// in front of the bench.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/simulation/building.hpp"

namespace sgt::bench {

struct PlacedObject {
  std::string class_name;
  NodeId node;
  MeshId mesh;
  Eigen::Isometry3d T_world_object;
};

struct PaperScene {
  Building building;
  std::shared_ptr<TriangleMesh> map;
  std::vector<std::shared_ptr<TriangleMesh>> object_meshes;  // per class, paper order
  std::vector<PlacedObject> objects;                         // the five on the bench
  std::unique_ptr<RaycastScene> scene;
  PinholeModel camera;
  SensorRays camera_rays, lidar_rays;
  Eigen::Isometry3d T_world_camera, T_world_lidar, T_world_base;
  bool real_meshes = false;
};

// Builds the scene; `extra_instances` more object instances are spread over the other rooms
// (out of the camera's view) to measure scaling. Cached per process for the building.
PaperScene makePaperScene(int extra_instances = 0);

// "real pbr_objects meshes" or "stand-ins" for benchmark labels.
std::string meshLabel(const PaperScene& s);

}  // namespace sgt::bench
