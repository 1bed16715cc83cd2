// FramePipeline: the contest between a lost track's pose and the detection that restarts it, and
// the orientation search for tracks just confirmed or restarted from a detection.
#include <algorithm>
#include <optional>
#include <utility>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/registration/orientation_search.hpp"

namespace sgt {

void FramePipeline::contestRestarts(const std::vector<RangeMeasurements>& sets) {
  const LifecycleOptions lo = lifecycleOptions();
  OrientationPrior prior;
  prior.world_up = Eigen::Vector3d::UnitZ();
  prior.weak_fits_score = true;
  for (Track& t : tracks_) {
    if (!t.before_restart ||
        !RestartContest::competes(sunkIntoMap(t.out.class_name, t.before_restart->pose())))
      continue;
    const ObjectClass& c = catalog_->get(t.out.class_name);
    // The incumbent first: it wins ties.
    const std::vector<Eigen::Isometry3d> candidates{t.before_restart->pose(), t.out.T_map_object};
    const OrientationChoice choice = chooseOrientation(
        scene_, {t.out.node, &c.symmetry}, candidates, sets, options_.orientation_refiner, prior);
    if (!RestartContest::detectionWins(choice.candidate, choice.quality.inlier_ratio, lo)) {
      // The track stays: its filter as before, no orientation search.
      t.filter = *t.before_restart;
      t.out.T_map_object = t.filter.pose();
      needs_orientation_.erase(
          std::remove(needs_orientation_.begin(), needs_orientation_.end(), t.out.id),
          needs_orientation_.end());
    }
    // Refinement goes on from the winner as it was, not as the contest's few rounds left it.
    scene_.setInstancePose(t.out.node, t.out.T_map_object);
    graph_.setWorldTransform(t.out.node, t.out.T_map_object);
  }
  scene_.commit();
}

void FramePipeline::settleDisputes(const std::vector<RangeMeasurements>& sets, double stamp) {
  OrientationPrior prior;
  prior.world_up = Eigen::Vector3d::UnitZ();
  bool contested = false;
  for (Track& t : tracks_) {
    if (!t.contested_by) continue;
    const Track::Contest contest = *t.contested_by;
    t.contested_by.reset();
    t.life.orientation_disputes = t.life.position_disputes = 0;
    const double last_search = t.life.last_orientation_search;
    if (stamp - last_search < options_.orientation_search_interval_s) continue;
    t.life.last_orientation_search = stamp;
    contested = true;
    const ObjectClass& c = catalog_->get(t.out.class_name);
    // The track first: it wins ties. A keypoint detector confuses an object with its turned twin
    // consistently (the shipped one turns the multimeter and the material box by half a turn),
    // so a detection turns a track only where the depth supports it.
    const std::vector<Eigen::Isometry3d> candidates{t.out.T_map_object, contest.pose};
    const OrientationChoice choice = chooseOrientation(
        scene_, {t.out.node, &c.symmetry}, candidates, sets, options_.orientation_refiner, prior);
    if (choice.candidate == 1) {
      t.out.T_map_object = choice.T_world_object;
      t.filter =
          PoseFilter(choice.T_world_object,
                     diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad),
                     options_.motion);
      if (contest.search_orientation) {  // its turn was held beside the object: search it here
        t.life.last_orientation_search = last_search;
        needs_orientation_.push_back(t.out.id);
      }
    }
    // Refinement goes on from the winner as it was, not as the contest's few rounds left it.
    scene_.setInstancePose(t.out.node, t.out.T_map_object);
    graph_.setWorldTransform(t.out.node, t.out.T_map_object);
  }
  if (contested) scene_.commit();
}

void FramePipeline::searchOrientations(const std::vector<RangeMeasurements>& sets, double stamp) {
  static const std::vector<Eigen::Matrix3d> rotations = cuboidRotations();
  OrientationPrior prior;
  prior.world_up = Eigen::Vector3d::UnitZ();  // the map's z (REP-103)
  int searched = 0;
  std::vector<std::string> waiting;
  for (const std::string& id : needs_orientation_) {
    if (searched >= options_.max_orientation_searches) {
      waiting.push_back(id);  // next frame
      continue;
    }
    const auto it = std::find_if(tracks_.begin(), tracks_.end(),
                                 [&](const Track& t) { return t.out.id == id; });
    if (it == tracks_.end()) continue;
    Track& t = *it;
    // A lost track restarting again soon waits.
    if (stamp - t.life.last_orientation_search < options_.orientation_search_interval_s) continue;
    t.life.last_orientation_search = stamp;
    const ObjectClass& c = catalog_->get(t.out.class_name);
    ++searched;
    const std::vector<Eigen::Isometry3d> candidates =
        orientationCandidates(t.out.T_map_object, c.box, rotations);
    const OrientationChoice choice = chooseOrientation(
        scene_, {t.out.node, &c.symmetry}, candidates, sets, options_.orientation_refiner, prior);
    if (choice.candidates_fitted == 0) continue;  // nothing to judge by: the detection stands
    t.out.T_map_object = choice.T_world_object;
    t.filter =
        PoseFilter(choice.T_world_object,
                   diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad),
                   options_.motion);
    graph_.setWorldTransform(t.out.node, choice.T_world_object);
  }
  needs_orientation_ = std::move(waiting);
}

}  // namespace sgt
