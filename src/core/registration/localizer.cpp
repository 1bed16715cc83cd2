#include "scene_graph_tracker/registration/localizer.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scene_graph_tracker/geometry/rigid.hpp"

namespace sgt {

const char* toString(LocalizeStatus s) {
  switch (s) {
    case LocalizeStatus::kOk:
      return "ok";
    case LocalizeStatus::kTooFewInliers:
      return "too few inliers";
    case LocalizeStatus::kDegenerate:
      return "degenerate (map points constrain too few directions)";
    case LocalizeStatus::kNotConverged:
      return "not converged";
  }
  return "?";
}

namespace {

// Whether point-to-plane pairs fix x, y and yaw: the smallest eigenvalue of their information
// (rows: yaw lever in units of the points' RMS distance, then the normals' x and y), per pair,
// is not negligible. A floor alone (vertical normals) or a corridor's two walls fail.
bool planarPoseObservable(const std::vector<Eigen::Vector3f>& points,
                          const std::vector<Eigen::Vector3f>& normals) {
  if (points.empty()) return false;
  double sq = 0.0;
  for (const Eigen::Vector3f& p : points) sq += p.head<2>().squaredNorm();
  const double scale = std::sqrt(sq / points.size());
  if (!(scale > 0.0)) return false;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points[i].cast<double>(), n = normals[i].cast<double>();
    const Eigen::Vector3d J((p.x() * n.y() - p.y() * n.x()) / scale, n.x(), n.y());
    H += J * J.transpose();
  }
  constexpr double kMinInformationPerPair = 1e-3;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H, Eigen::EigenvaluesOnly)
             .eigenvalues()(0) >= kMinInformationPerPair * points.size();
}

}  // namespace

LocalizeResult Localizer::localize(const RaycastScene& scene,
                                   const std::vector<RangeMeasurements>& measurements,
                                   const Eigen::Isometry3d& T_map_base_prior) const {
  if (scene.staticMapNode() == kNoNode)
    throw std::logic_error("Localizer: the scene has no static map");
  LocalizeResult result;
  result.T_map_base = result.T_map_base_estimate = T_map_base_prior;
  NodeGroups groups;
  groups.set(scene.staticMapNode(), 0);
  const Eigen::Isometry3d T_base_map_prior = T_map_base_prior.inverse();
  std::vector<RangeMeasurements> moved = measurements;  // sensor poses follow the estimate
  std::vector<TileSet> tiles;
  for (const RangeMeasurements& m : measurements) {
    // Strides thin the grids; one ray per return (PointRays: a laser scan's few hundred beams,
    // an unorganized cloud) is cast whole.
    const int stride = std::holds_alternative<PinholeModel>(m.model)         ? options_.image_stride
                       : std::holds_alternative<SpinningLidarModel>(m.model) ? options_.scan_stride
                                                                             : 1;
    const GridRect whole{0, 0, m.rays->width, m.rays->height};
    tiles.push_back(TileSet::covering(*m.rays, std::vector<GridRect>{whole}, stride));
  }

  Eigen::Isometry3d T = T_map_base_prior;
  float max_dist = options_.max_dist_start;
  bool converged = false, degenerate = false;
  RayHits hits;
  std::vector<RayPair> pairs;
  int expected = 0;
  for (int round = 0; round < options_.rounds && !converged; ++round) {
    pairs.clear();
    expected = 0;
    for (std::size_t s = 0; s < measurements.size(); ++s) {
      moved[s].T_world_sensor = T * (T_base_map_prior * measurements[s].T_world_sensor);
      PairingStats stats;
      auto p = collectRayPairs(scene, moved[s], tiles[s], groups, max_dist, hits, &stats);
      pairs.insert(pairs.end(), p[0].begin(), p[0].end());
      expected += stats.expected[0];
      result.rays_cast += tiles[s].rayCount();
    }
    result.rounds = round + 1;
    // In the current base frame: measured points move with the robot, map points are fixed.
    const Eigen::Isometry3f T_base_map = T.inverse().cast<float>();
    std::vector<Eigen::Vector3f> moving, fixed, normals;
    moving.reserve(pairs.size()), fixed.reserve(pairs.size()), normals.reserve(pairs.size());
    double sq_residual = 0.0;
    std::vector<float> abs_residual;
    abs_residual.reserve(pairs.size());
    for (const RayPair& p : pairs) {
      moving.push_back(T_base_map * p.measured);
      fixed.push_back(T_base_map * p.model);
      normals.push_back(T_base_map.linear() * p.normal);
      const double r = (p.measured - p.model).norm();
      abs_residual.push_back(static_cast<float>(r)), sq_residual += r * r;
    }
    result.inliers = static_cast<int>(pairs.size());
    result.expected = expected;
    if (result.inliers < options_.min_inliers) break;
    result.rmse = std::sqrt(sq_residual / pairs.size());
    AlignmentOptions alignment = options_.alignment;
    if (options_.planar) {
      alignment.free_dofs = {false, false, true, true, true, false};  // base frame: z up
      // A planar set (a laser scan's plane) still fixes x, y and yaw; what it needs is surfaces
      // facing several ways, which the information of those three says.
      alignment.reject_planar = false;
      if (!planarPoseObservable(moving, normals)) {
        degenerate = true;
        break;
      }
    }
    const IterativeAlignment a =
        alignPairs(moving, fixed, normals, NormalSide::kFixed, options_.solver, options_.steps,
                   options_.step_tolerance, alignment);
    if (a.status == AlignmentStatus::kCollinear || a.status == AlignmentStatus::kPlanar) {
      degenerate = true;
      break;
    }
    if (a.steps == 0) break;
    T = rigid(T * a.T);
    const double moved_t = a.T.translation().norm(),
                 moved_r = Eigen::AngleAxisd(a.T.linear()).angle();
    // Robust scale of the residuals (1.4826 x median absolute residual = sigma for Gaussian
    // noise): people and moved things inside the threshold must not hold it open.
    std::nth_element(abs_residual.begin(), abs_residual.begin() + abs_residual.size() / 2,
                     abs_residual.end());
    const float sigma = 1.4826f * abs_residual[abs_residual.size() / 2];
    const float next =
        std::max(options_.max_dist_min, std::min(max_dist, options_.residual_factor * sigma));
    converged = moved_t < options_.converged_translation && moved_r < options_.converged_rotation &&
                max_dist <= options_.max_dist_min;
    max_dist = next;
  }
  result.final_threshold = max_dist;
  result.T_map_base_estimate = T;
  result.inlier_ratio =
      result.expected > 0 ? static_cast<double>(result.inliers) / result.expected : 0.0;
  if (degenerate)
    result.status = LocalizeStatus::kDegenerate;
  else if (result.inliers < options_.min_inliers || result.inlier_ratio < options_.min_inlier_ratio)
    result.status = LocalizeStatus::kTooFewInliers;
  else if (!converged)
    result.status = LocalizeStatus::kNotConverged;
  else
    result.status = LocalizeStatus::kOk;
  if (result.status == LocalizeStatus::kOk) result.T_map_base = T;
  return result;
}

}  // namespace sgt
