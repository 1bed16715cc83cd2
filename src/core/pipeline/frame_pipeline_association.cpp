// FramePipeline: prediction of the tracks to a frame and association of the hypotheses with them.
#include <algorithm>
#include <limits>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/tracking/assignment.hpp"

namespace sgt {
namespace {

// 99.9 % of a 6-dof Gaussian lie within this squared Mahalanobis distance.
constexpr double kGate6Dof = 22.46;

}  // namespace

void FramePipeline::predict(double stamp) {
  const double dt = last_stamp_ >= 0.0 ? stamp - last_stamp_ : 0.0;
  last_stamp_ = stamp;
  for (Track& t : tracks_) {
    if (dt > 0.0 && t.out.quality.status != RefineStatus::kOk) t.filter.damp(dt);  // coasting
    if (dt > 0.0) t.filter.predict(dt);
  }
  // A track under the world follows its filter; a child keeps its pose relative to its parent
  // (moved just before it), so what is in or on a carried object is carried along.
  for (std::size_t k : parentsFirst()) {
    Track& t = tracks_[k];
    if (!isChild(t.out.node)) graph_.setWorldTransform(t.out.node, t.filter.pose());
    t.out.T_map_object = graph_.worldTransform(t.out.node);
    scene_.setInstancePose(t.out.node, t.out.T_map_object);
  }
}

std::vector<std::size_t> FramePipeline::parentsFirst() const {
  std::vector<std::pair<int, std::size_t>> by_depth;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    int depth = 0;
    for (NodeId n = tracks_[k].out.node; graph_.node(n).parent != kWorldNode;
         n = graph_.node(n).parent)
      ++depth;
    by_depth.emplace_back(depth, k);
  }
  std::sort(by_depth.begin(), by_depth.end());
  std::vector<std::size_t> order;
  for (const auto& [depth, k] : by_depth) order.push_back(k);
  return order;
}

Eigen::MatrixXd FramePipeline::associationCosts(const std::vector<PoseHypothesis>& hypotheses,
                                                const std::vector<Eigen::Isometry3d>& in_map,
                                                double forbidden) const {
  const LifecycleOptions lo = lifecycleOptions();
  Eigen::MatrixXd cost(hypotheses.size(), tracks_.size());
  for (std::size_t h = 0; h < hypotheses.size(); ++h)
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      const TrackedObject& o = tracks_[k].out;
      const double d = (o.T_map_object.translation() - in_map[h].translation()).norm();
      const double gate =
          DetectionAssociation::gate(o.quality.status, isChild(o.node), tracks_[k].life, lo);
      cost(h, k) = o.class_name == hypotheses[h].class_name && d < gate ? d : forbidden;
    }
  return cost;
}

void FramePipeline::associate(const std::vector<PoseHypothesis>& hypotheses, double stamp,
                              PipelineResult& out) {
  const double forbidden = std::numeric_limits<double>::max();
  std::vector<Eigen::Isometry3d> in_map(hypotheses.size());
  for (std::size_t h = 0; h < hypotheses.size(); ++h)
    in_map[h] = out.T_map_base * hypotheses[h].T_base_object;
  const std::vector<int> match =
      assignMinCost(associationCosts(hypotheses, in_map, forbidden), forbidden);
  // Where this frame's detections placed an object (matched ones first): a second detection
  // there is the same object seen twice, not another one.
  std::vector<std::size_t> placed;
  for (std::size_t h = 0; h < hypotheses.size(); ++h)
    if (match[h] >= 0) placed.push_back(h);
  for (std::size_t h = 0; h < hypotheses.size(); ++h) {
    if (match[h] < 0) {  // a new object, or a false detection: a tentative track either way
      if (overlapsPlaced(hypotheses, in_map, placed, h)) {
        ++out.hypotheses_duplicate;  // a duplicate detection
        continue;
      }
      if (!roomForTrack(hypotheses[h].class_name)) {
        ++out.hypotheses_over_limits;
        continue;
      }
      // An object whose track was seen missing elsewhere, or a new one: the former's id.
      const std::string id = unlocated_.claim(hypotheses[h].class_name, in_map[h].translation());
      startTrack(hypotheses[h].class_name, in_map[h], stamp, id);
      tracks_.back().life.detections = 1;
      placed.push_back(h);
      continue;
    }
    Track& t = tracks_[match[h]];
    if (hypotheses[h].up_to_box_half_turns) in_map[h] = nearestBoxHalfTurn(t, in_map[h]);
    t.life.last_hypothesis = stamp, t.life.unseen_s = 0.0;
    ++t.life.detections;
    if (DetectionAssociation::restarts(t.out.quality.status, placedByWeakFit(t)))
      restartFromDetection(t, in_map[h]);
    else
      fuseOrDispute(t, in_map[h]);
  }
}

void FramePipeline::fuseOrDispute(Track& t, const Eigen::Isometry3d& T_detected) {
  noteDispute(t, T_detected);
  if (!options_.fuse_hypotheses || t.contested_by) return;
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  const Symmetry* symmetry = &catalog_->get(t.out.class_name).symmetry;
  // A child is where its parent holds it, not where its filter predicts: the detection corrects
  // that pose, with the filter's uncertainty.
  PoseFilter at_pose = isChild(t.out.node) ? PoseFilter(t.out.T_map_object,
                                                        t.filter.poseCovariance(), options_.motion)
                                           : t.filter;
  if (at_pose.distance2(T_detected, C, symmetry) > kGate6Dof) return;
  at_pose.update(T_detected, C, symmetry);
  if (!isChild(t.out.node)) t.filter = at_pose;
  t.out.T_map_object = at_pose.pose();
  scene_.setInstancePose(t.out.node, t.out.T_map_object);
  graph_.setWorldTransform(t.out.node, t.out.T_map_object);
}

Eigen::Isometry3d FramePipeline::nearestBoxHalfTurn(const Track& t,
                                                    const Eigen::Isometry3d& T_detected) const {
  const ObjectClass& object = catalog_->get(t.out.class_name);
  const std::vector<Eigen::Isometry3d> symmetries = object.symmetry.sampled();
  Eigen::Isometry3d best = T_detected;
  double best_angle = M_PI + 1.0;
  for (const Eigen::Isometry3d& turn : boxHalfTurns(object.box)) {
    const Eigen::Isometry3d turned = T_detected * turn;
    const double angle =
        angleUpToSymmetries(t.out.T_map_object.linear(), turned.linear(), symmetries);
    if (angle < best_angle) best = turned, best_angle = angle;
  }
  return best;
}

void FramePipeline::noteDispute(Track& t, const Eigen::Isometry3d& T_detected) {
  const LifecycleOptions lo = lifecycleOptions();
  const double angle = angleUpToSymmetries(t.out.T_map_object.linear(), T_detected.linear(),
                                           catalog_->get(t.out.class_name).symmetry.sampled());
  t.life.orientation_disputes = OrientationDispute::next(t.life.orientation_disputes, angle, lo);
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  t.life.position_disputes =
      PositionDispute::next(t.life.position_disputes, t.filter.shiftDistance2(T_detected, C), lo);
  if (OrientationDispute::contested(t.life.orientation_disputes, lo)) {
    t.contested_by = Track::Contest{T_detected, false};
  } else if (PositionDispute::contested(t.life.position_disputes, lo)) {
    Eigen::Isometry3d moved = t.out.T_map_object;
    moved.translation() = T_detected.translation();
    t.contested_by = Track::Contest{moved, true};
  }
}

bool FramePipeline::overlapsPlaced(const std::vector<PoseHypothesis>& hypotheses,
                                   const std::vector<Eigen::Isometry3d>& in_map,
                                   const std::vector<std::size_t>& placed, std::size_t h) const {
  const std::string& name = hypotheses[h].class_name;
  const double radius = 0.5 * catalog_->get(name).box.sizes().minCoeff();
  return std::any_of(placed.begin(), placed.end(), [&](std::size_t p) {
    return hypotheses[p].class_name == name &&
           (in_map[p].translation() - in_map[h].translation()).norm() < radius;
  });
}

bool FramePipeline::roomForTrack(const std::string& class_name) const {
  if (tracks_.size() >= static_cast<std::size_t>(std::max(0, options_.max_tracks))) return false;
  const auto of_class = std::count_if(tracks_.begin(), tracks_.end(), [&](const Track& t) {
    return t.out.class_name == class_name;
  });
  return of_class < options_.max_tracks_per_class;
}

void FramePipeline::restartFromDetection(Track& t, const Eigen::Isometry3d& T_map_object) {
  if (t.life.state == TrackState::kLost) t.before_restart = t.filter;  // for the restart contest
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  const Symmetry* symmetry = &catalog_->get(t.out.class_name).symmetry;
  if (options_.restart_replaces_outliers &&
      t.filter.distance2(T_map_object, C, symmetry) > kGate6Dof)
    t.filter = PoseFilter(T_map_object, C, options_.motion);
  else
    t.filter.update(T_map_object, C, symmetry);
  t.out.T_map_object = T_map_object;
  scene_.setInstancePose(t.out.node, T_map_object);
  needs_orientation_.push_back(t.out.id);
}

}  // namespace sgt
