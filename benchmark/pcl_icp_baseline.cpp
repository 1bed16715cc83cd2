// PCL ICP baseline (see pcl_icp_baseline.hpp). PCL_NO_PRECOMPILE instantiates PCL's templates
// (kd-tree, search, ICP) here instead of using Debian's builds in libpcl_kdtree / libpcl_search,
// whose FLANN search goes through OpenMP per query: ~10x slower per frame on the paper's frame.
// Built with the project's -march=native; a generic -march=x86-64 build measured the same.
#define PCL_NO_PRECOMPILE
#include "pcl_icp_baseline.hpp"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

namespace sgt::bench {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

pcl::PointNormal pointNormal(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  pcl::PointNormal q;
  q.getVector3fMap() = p;
  q.getNormalVector3fMap() = n;
  q.curvature = 0.0f;
  return q;
}

// ICP of one object, in its frame at the initial pose. Target: the model's surface samples.
// Source: the measured points inside the grown box (what pcl::CropBox at the initial pose keeps).
// Returns the ICP transform source -> target; identity when too few points were cropped.
//
// Not in the world frame: the point-to-plane LLS linearises the rotation about the origin, and
// with the objects metres away from it its steps overshoot (ADD-S ~300 mm at 0 %, 30 mm).
Eigen::Matrix4f alignObject(const PclIcpModel& model,
                            const std::vector<Eigen::Vector3f>& world_points,
                            const Eigen::Isometry3f& T_init, const PclIcpOptions& o) {
  Cloud::Ptr source(new Cloud), target(new Cloud);
  const Eigen::Isometry3f T_inv = T_init.inverse();
  const Eigen::Vector3f lo = model.box_min.array() - o.crop_margin,
                        hi = model.box_max.array() + o.crop_margin;
  for (const Eigen::Vector3f& p : world_points) {
    const Eigen::Vector3f q = T_inv * p;
    if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all())
      source->push_back(pointNormal(q, Eigen::Vector3f::Zero()));  // source normals are not used
  }
  if (static_cast<int>(source->size()) < o.min_points) return Eigen::Matrix4f::Identity();
  target->reserve(model.points.size());
  for (std::size_t i = 0; i < model.points.size(); ++i)
    target->push_back(pointNormal(model.points[i], model.normals[i]));

  auto run = [&](auto& icp) {
    icp.setMaximumIterations(o.max_iterations);
    icp.setMaxCorrespondenceDistance(o.max_correspondence_distance);
    icp.setTransformationEpsilon(o.transformation_epsilon);
    icp.setInputSource(source);
    icp.setInputTarget(target);  // builds the target's kd-tree
    Cloud aligned;
    icp.align(aligned);
    return icp.getFinalTransformation();
  };
  if (o.point_to_plane) {
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal>
        icp;  // point-to-plane LLS
    return run(icp);
  }
  pcl::IterativeClosestPoint<pcl::PointNormal, pcl::PointNormal> icp;  // point-to-point (SVD)
  return run(icp);
}

}  // namespace

std::vector<PlainPose> pclIcpRefine(const std::vector<PclIcpModel>& models,
                                    const std::vector<Eigen::Vector3f>& world_points,
                                    const std::vector<PlainPose>& initial,
                                    const PclIcpOptions& options) {
  std::vector<PlainPose> result(models.size());
  tbb::parallel_for(std::size_t{0}, models.size(), [&](std::size_t k) {
    const Eigen::Isometry3d T_init(Eigen::Matrix4d(initial[k]));
    const Eigen::Matrix4f icp = alignObject(models[k], world_points, T_init.cast<float>(), options);
    // ICP moves the measurement (in the initial object frame) onto the model:
    // T_icp * T_init^-1 * T_true = I.
    const Eigen::Isometry3d T_icp(icp.cast<double>());
    result[k] = (T_init * T_icp.inverse()).matrix();
  });
  return result;
}

}  // namespace sgt::bench
