// FramePipeline: how well a track is seen, for the weight of its fits and for evidence of absence.
#include <algorithm>
#include <cmath>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/registration/ray_regions.hpp"
#include "scene_graph_tracker/relations/oriented_box.hpp"
#include "scene_graph_tracker/relations/support_rays.hpp"

namespace sgt {

double FramePipeline::fitWeakness(const TrackedObject& o,
                                  const std::vector<RangeMeasurements>& sets) const {
  const double few =
      static_cast<double>(options_.well_seen_points) / std::max(1, o.quality.inliers);
  double range = 0.0;  // to the nearest sensor of the frame
  for (std::size_t s = 0; s < sets.size(); ++s) {
    const double d = (o.T_map_object.translation() - sets[s].T_world_sensor.translation()).norm();
    range = s == 0 ? d : std::min(range, d);
  }
  const double far =
      options_.far_fit_from_m > 0.0 ? std::pow(range / options_.far_fit_from_m, 4) : 1.0;
  return std::max(1.0, few) * std::max(1.0, far);
}

namespace {

// Rays of the sets near `extent` (as refinement's last round casts them) with a valid
// measurement that hit `node`: all of them; those whose measurement lies within `threshold` of
// the hit (agreeing); and those measured before the hit by more than the threshold and at most
// `window` (in front; window_sigmas of the depth noise). Rays stop at the measurement plus the
// window, so a ray blocked by something closer does not count.
struct RayCounts {
  int reaching = 0, agreeing = 0, in_front = 0;
  // The rays whose measurement lies beyond the surface: they pass through where it should be.
  int seenThrough() const { return reaching - agreeing - in_front; }
};
RayCounts countRays(const RaycastScene& scene, NodeId node, const ObjectExtent& extent,
                    const std::vector<RangeMeasurements>& sets, const RefinerOptions& ro,
                    float window_sigmas) {
  RayCounts c;
  for (const RangeMeasurements& m : sets) {
    const HitsLease lease = scratchHits(m.rays->width, m.rays->height);
    RayHits& hits = *lease;
    const bool coarse =
        !ro.full_resolution_last_round && std::holds_alternative<PinholeModel>(m.model);
    const TileSet tiles = TileSet::covering(*m.rays, raysNearObjects(m, {extent}, ro.roi_margin),
                                            coarse ? ro.ray_stride : 1);
    const RangeTolerance threshold = noiseBand(m, ro.max_dist_last, ro);
    const RangeTolerance window(m, ro.max_dist_last, ro.noise,
                                std::max(window_sigmas, ro.noise_sigmas));
    scene.cast(*m.rays, m.T_world_sensor, hits, &tiles, CastLimit{&m.range, window},
               kRangeAndNodeOnly);
    tiles.forEachRay(*m.rays, [&](std::size_t i) {
      if (hits.node[i] != node || !m.valid(i)) return;
      ++c.reaching;
      const float beyond = hits.range[i] - m.range[i];  // > 0: the measurement is before it
      const float t = threshold.at(m.range[i]);
      c.agreeing += std::abs(beyond) < t;
      c.in_front += beyond >= t && beyond <= window.at(m.range[i]);
    });
  }
  return c;
}

}  // namespace

Sighting FramePipeline::sight(std::size_t k, const std::vector<RangeMeasurements>& sets,
                              double* agreement) {
  if (agreement) *agreement = -1.0;
  const NodeId node = tracks_[k].out.node;
  const ObjectExtent extent{scene_.instancePose(node), scene_.meshBox(scene_.instanceMesh(node))};
  const RefinerOptions ro = withSensorNoise(options_.refiner);
  const RayCounts seen =
      countRays(scene_, node, extent, sets, ro, static_cast<float>(options_.absence_noise_sigmas));
  if (seen.reaching < ro.alignment.min_points) return Sighting::kHidden;
  if (agreement)
    *agreement = static_cast<double>(seen.agreeing) / std::max(1, seen.reaching - seen.in_front);
  // Most rays that reach it pass through where its surface should be, however much of it other
  // tracks hide: a ray stopped by one is not counted, one that passes them is evidence.
  const bool missing = seen.seenThrough() > (1.0 - ro.min_inlier_ratio) * seen.reaching;
  return missing ? Sighting::kMissing : Sighting::kThere;
}

bool FramePipeline::dropsOutOfSight(std::size_t k, const std::vector<RangeMeasurements>& sets) {
  Track& t = tracks_[k];
  relations::SupportOptions below_options;
  below_options.max_gap = options_.unseen_drop_m;
  const Eigen::AlignedBox3d box = catalog_->get(t.out.class_name).box.cast<double>();
  const relations::Support below = relations::supportBelow(
      scene_, relations::orientedBox(box, t.out.T_map_object), t.out.node, below_options);
  if (below.node == kNoNode || !(below.gap > 0.0)) return false;
  const Eigen::Isometry3d where = t.out.T_map_object;
  Eigen::Isometry3d dropped = where;
  dropped.translation().z() -= below.gap;
  scene_.setInstancePose(t.out.node, dropped);
  scene_.commit();
  if (sight(k, sets) == Sighting::kMissing) {  // missing there too
    scene_.setInstancePose(t.out.node, where);
    scene_.commit();
    return false;
  }
  t.out.T_map_object = dropped;
  t.filter = PoseFilter(
      dropped, diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad),
      options_.motion);
  graph_.setWorldTransform(t.out.node, dropped);
  return true;
}

bool FramePipeline::sunkIntoMap(const std::string& class_name,
                                const Eigen::Isometry3d& T_map_object) const {
  const MeshId map = scene_.staticMapMesh();
  if (map < 0 || options_.max_sunk_fraction >= 1.0) return false;
  const std::vector<Eigen::Vector3f>& samples = class_samples_.at(class_name);
  const Eigen::Isometry3f T = T_map_object.cast<float>();
  const float tolerance = static_cast<float>(options_.sink_tolerance_m);
  std::size_t sunk = 0;
  for (const Eigen::Vector3f& p_object : samples) {
    const Eigen::Vector3f p = T * p_object;
    SurfacePoint q;  // the map is instanced with the identity: its frame is the map frame
    if (!scene_.closestPoint(map, p, 5.0f * tolerance, q) || q.distance <= tolerance) continue;
    sunk += (p - q.point).dot(q.normal) < 0.0f;  // behind the closest face
  }
  return static_cast<double>(sunk) >
         options_.max_sunk_fraction * static_cast<double>(samples.size());
}

}  // namespace sgt
