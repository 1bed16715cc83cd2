// PCL ICP baseline for the refinement benchmark: per object, the measured points inside the
// object's box at its initial pose (grown by a margin) are registered to surface samples of the
// object's mesh at that pose, with pcl::IterativeClosestPoint (point-to-point, SVD) or
// pcl::IterativeClosestPointWithNormals (point-to-plane, linear least squares).
//
// Only plain data crosses this header (no PCL types, no over-aligned Eigen types), so
// pcl_icp_baseline.cpp may be compiled with other flags than the rest of the benchmark.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace sgt::bench {

// Homogeneous world <- object transform without Eigen's alignment (same layout under any -march).
using PlainPose = Eigen::Matrix<double, 4, 4, Eigen::DontAlign>;

struct PclIcpModel {
  std::vector<Eigen::Vector3f> points, normals;  // surface samples, object frame
  Eigen::Vector3f box_min, box_max;              // bounding box, object frame
};

struct PclIcpOptions {
  bool point_to_plane = true;
  int max_iterations = 24;
  double max_correspondence_distance = 0.03;  // m
  float crop_margin = 0.04f;                  // m, the box grows by this on every side
  double transformation_epsilon = 1e-12;  // stop below: step translation^2 (m^2), 1 - cos(angle)
  int min_points = 12;                    // fewer cropped points: the initial pose is kept
};

// Refines every object k from initial[k] against `world_points` (measured points, world frame).
// Objects run in parallel (tbb::parallel_for). Returns the corrected world <- object poses.
std::vector<PlainPose> pclIcpRefine(const std::vector<PclIcpModel>& models,
                                    const std::vector<Eigen::Vector3f>& world_points,
                                    const std::vector<PlainPose>& initial,
                                    const PclIcpOptions& options);

}  // namespace sgt::bench
