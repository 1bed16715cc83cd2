// How well poses explain a depth image, with or without ground truth: the posed meshes are
// rendered into the camera together (each may hide another) and each object's rendered depth is
// compared with the measured depth on its visible pixels (the pixels where it is the first
// surface and the camera has a return). The median |measured z - rendered z| says whether the
// pose sits on the object's own surface; unknown things in front of it (a hand, clutter) are a
// minority of its pixels and do not move the median.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "scene_graph_tracker/registration/object_refiner.hpp"
#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

struct PosedObject {
  std::string id, class_name;
  Eigen::Isometry3d T_camera_object = Eigen::Isometry3d::Identity();
};

struct SurfaceFit {
  std::size_t visible_pixels = 0;  // rendered first and measured (of the cast rays)
  double median_residual_m = 0.0;  // NaN without visible pixels
};

class SurfaceFitter {
 public:
  // `stride` > 1 casts every stride-th ray in x and y (the median needs far fewer than all).
  explicit SurfaceFitter(std::shared_ptr<const ObjectCatalog> catalog, int stride = 1);
  // Per object of `objects` (same order). `camera` is a pinhole depth image's measurements (the
  // objects' poses are in its frame). With `owner`, also the index into `objects` of the first
  // surface of every pixel (-1: none; rays not cast are -1 too), row-major.
  std::vector<SurfaceFit> fit(const RangeMeasurements& camera,
                              const std::vector<PosedObject>& objects,
                              std::vector<int>* owner = nullptr);
  // What that mesh alone reaches on this depth image: `object` refined from its pose by an
  // ObjectRefiner with `options`, with no other object and no map, on the rays that hit it only
  // (no pulls: without a map every unexplained point would pull), twice (the second pass starts
  // where the first converged); the fit of the refined pose. `object` keeps the refined pose.
  SurfaceFit fitAlone(const RangeMeasurements& camera, PosedObject& object,
                      const RefinerOptions& options = {});

 private:
  MeshId meshOf(const std::string& class_name);
  void pose(const std::vector<PosedObject>& objects);

  std::shared_ptr<const ObjectCatalog> catalog_;
  int stride_;
  RaycastScene scene_;
  std::map<std::string, MeshId> meshes_;
  std::size_t instances_ = 0;
  RayHits hits_;
};

// Draws the outline of each object's pixels in `owner` (as from SurfaceFitter::fit) on `image`
// (8-bit, 3 channels, the owner's size) in colour `colours[k % size]`, `thickness` px wide.
void drawOutlines(cv::Mat& image, const std::vector<int>& owner, std::size_t objects,
                  const std::vector<cv::Scalar>& colours, int thickness = 2);

}  // namespace sgt
