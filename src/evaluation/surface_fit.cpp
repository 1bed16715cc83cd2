#include "scene_graph_tracker/evaluation/surface_fit.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace sgt {
namespace {

constexpr NodeId kFirstNode = 1;  // object k is node kFirstNode + k

double median(std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

SurfaceFitter::SurfaceFitter(std::shared_ptr<const ObjectCatalog> catalog, int stride)
    : catalog_(std::move(catalog)), stride_(std::max(1, stride)) {}

MeshId SurfaceFitter::meshOf(const std::string& class_name) {
  const auto it = meshes_.find(class_name);
  if (it != meshes_.end()) return it->second;
  return meshes_[class_name] = scene_.addMesh(catalog_->get(class_name).mesh);
}

void SurfaceFitter::pose(const std::vector<PosedObject>& objects) {
  for (std::size_t k = 0; k < instances_; ++k)
    scene_.removeInstance(static_cast<NodeId>(kFirstNode + k));
  for (std::size_t k = 0; k < objects.size(); ++k)
    scene_.addInstance(static_cast<NodeId>(kFirstNode + k), meshOf(objects[k].class_name),
                       objects[k].T_camera_object);
  instances_ = objects.size();
  scene_.commit();
}

std::vector<SurfaceFit> SurfaceFitter::fit(const RangeMeasurements& camera,
                                           const std::vector<PosedObject>& objects,
                                           std::vector<int>* owner) {
  pose(objects);
  const SensorRays& rays = *camera.rays;
  const TileSet tiles = TileSet::covering(rays, {{0, 0, rays.width, rays.height}}, stride_);
  hits_.resize(rays.width, rays.height);
  std::fill(hits_.node.begin(), hits_.node.end(), kNoNode);
  scene_.cast(rays, Eigen::Isometry3d::Identity(), hits_, &tiles);
  std::vector<std::vector<double>> residuals(objects.size());
  if (owner) owner->assign(rays.directions.size(), -1);
  tiles.forEachRay(rays, [&](std::size_t i) {
    if (!hits_.hit(i)) return;
    const auto k = static_cast<std::size_t>(hits_.node[i] - kFirstNode);
    if (owner) (*owner)[i] = static_cast<int>(k);
    if (!camera.valid(i)) return;
    const double dz = rays.directions[i].z();
    residuals[k].push_back(std::abs(camera.range[i] - hits_.range[i]) * dz);
  });
  std::vector<SurfaceFit> out(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k)
    out[k] = {residuals[k].size(), median(residuals[k])};
  return out;
}

SurfaceFit SurfaceFitter::fitAlone(const RangeMeasurements& camera, PosedObject& object,
                                   const RefinerOptions& options) {
  // The refiner works in the measurements' world frame; the fitter's scene in the camera's.
  PosedObject in_world = object;
  in_world.T_camera_object = camera.T_world_sensor * object.T_camera_object;
  pose({in_world});
  RefinerOptions own_rays = options;
  own_rays.pull_radius = 0.0f;  // no map here: unexplained points are anything's
  const ObjectRefiner refiner(own_rays);
  const std::vector<RangeMeasurements> measurements{camera};
  for (int pass = 0; pass < 2; ++pass) {
    const RefineResult r = refiner.refine(scene_, {{kFirstNode, nullptr}}, measurements);
    if (r.objects.empty()) break;
    in_world.T_camera_object = r.objects.front().T_world_object;
  }
  object.T_camera_object = camera.T_world_sensor.inverse() * in_world.T_camera_object;
  return fit(camera, {object}).front();
}

void drawOutlines(cv::Mat& image, const std::vector<int>& owner, std::size_t objects,
                  const std::vector<cv::Scalar>& colours, int thickness) {
  if (owner.size() != image.total() || colours.empty()) return;
  const cv::Mat owner_image(image.rows, image.cols, CV_32SC1, const_cast<int*>(owner.data()));
  for (std::size_t k = 0; k < objects; ++k) {
    cv::Mat mask = owner_image == static_cast<int>(k);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(image, contours, -1, colours[k % colours.size()], thickness, cv::LINE_AA);
  }
}

}  // namespace sgt
