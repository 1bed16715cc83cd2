#include "scene_graph_tracker/registration/object_refiner.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "scene_graph_tracker/registration/ray_correspondences.hpp"
#include "scene_graph_tracker/registration/ray_regions.hpp"
#include "scene_graph_tracker/registration/unexplained_pairs.hpp"

namespace sgt {

const char* toString(RefineStatus s) {
  switch (s) {
    case RefineStatus::kOk:
      return "ok";
    case RefineStatus::kNotVisible:
      return "not visible";
    case RefineStatus::kTooFewPoints:
      return "too few points";
    case RefineStatus::kDegenerate:
      return "degenerate (planar or collinear points)";
    case RefineStatus::kFalseHypothesis:
      return "false hypothesis (few inliers)";
    case RefineStatus::kImplausibleTurn:
      return "implausible turn (beyond the track's motion gate)";
  }
  return "?";
}

namespace {

// Removes the rotation about each continuous symmetry axis (object frame) from the step
// T_start -> T_new, so refinement never spins an object about an axis it cannot observe.
Eigen::Isometry3d withoutSymmetricTwist(const Eigen::Isometry3d& T_start,
                                        const Eigen::Isometry3d& T_new, const Symmetry* symmetry) {
  if (!symmetry || symmetry->continuous.empty()) return T_new;
  Eigen::Isometry3d rel = T_start.inverse() * T_new;
  for (const auto& c : symmetry->continuous) {
    const Eigen::Quaterniond q(rel.linear());
    const Eigen::Vector3d proj = c.axis * c.axis.dot(q.vec());
    Eigen::Quaterniond twist(q.w(), proj.x(), proj.y(), proj.z());
    if (twist.norm() < 1e-12) continue;
    twist.normalize();
    Eigen::Isometry3d untwist = Eigen::Isometry3d::Identity();
    untwist.translate(c.offset);
    untwist.rotate(twist.inverse());
    untwist.translate(-c.offset);
    rel = rel * untwist;
  }
  return T_start * rel;
}

// How far the step from `from` to `to` moves the farthest corner of `box` (object frame).
double cornerShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to,
                   const Eigen::AlignedBox3f& box) {
  double largest = 0.0;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p =
        box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)).cast<double>();
    largest = std::max(largest, (to * p - from * p).norm());
  }
  return largest;
}

// Scales the update `delta` (object frame) along its screw so that no corner of `box` moves by
// more than `limit`: a few near-degenerate pairs (a thin object's sliver) can otherwise produce
// an arbitrarily large step that no pair of the round supports.
Eigen::Isometry3d limitStep(const Eigen::Isometry3d& delta, const Eigen::AlignedBox3f& box,
                            double limit) {
  const double largest = cornerShift(Eigen::Isometry3d::Identity(), delta, box);
  if (largest <= limit) return delta;
  const double f = limit / largest;
  const Eigen::AngleAxisd aa(delta.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::AngleAxisd(aa.angle() * f, aa.axis()).toRotationMatrix();
  out.translation() = delta.translation() * f;
  return out;
}

// An object's pairs of a round and each pair's weight in the fit (all 1 unless
// RefinerOptions::weigh_by_noise).
struct FitPairs {
  std::vector<RayPair> pairs;
  std::vector<float> weight;
  void add(const RayPair& p, float w) { pairs.push_back(p), weight.push_back(w); }
};

// What one cast ray of `m` near object `e` tells the fit: the rays of the base sampling it stands
// for over the variance of its sensor's noise at the object's range.
double rayInformation(const RangeMeasurements& m, const ObjectExtent& e, float rays,
                      const RangeNoise& noise) {
  const Eigen::Vector3d centre = e.T_world_object * e.box.center().cast<double>();
  const float range = static_cast<float>((centre - m.T_world_sensor.translation()).norm());
  const double sigma = std::max(1e-4f, noise.sigma(m, range));
  return rays / (sigma * sigma);
}

// A point-to-point pair as three point-to-plane rows along orthonormal axes (the linear step sums
// squared plane residuals, so the three rows sum to the squared distance).
void appendPointToPoint(RayPair p, float w, FitPairs& out) {
  for (int a = 0; a < 3; ++a) {
    p.normal = Eigen::Vector3f::Unit(a);
    out.add(p, w);
  }
}

// The pairs the fit moves the object by: those within the round's threshold. Rays in the wider
// band of the sensor's noise (`widened`) count as the object's (inliers, assignment, no pulls) but
// do not move it: a far object's band reaches its identical neighbour.
void appendAlignmentPairs(const std::vector<RayPair>& found, bool widened, float max_dist,
                          float weight, FitPairs& out) {
  for (const RayPair& p : found)
    if (!widened || (p.model - p.measured).norm() < max_dist) out.add(p, weight);
}

// An object's pairs of its last round per measurement set, the rays each cast ray stands for, and
// the rays that hit it (weighted): what its quality is computed from.
struct LastPairs {
  std::vector<std::vector<RayPair>> pairs;
  std::vector<float> weight;
  double expected = 0.0;
};

// Drops the pairs beyond `tolerance` (per set): those a cast at it would not have paired.
void keepWithin(LastPairs& l, const std::vector<RangeTolerance>& tolerance,
                const std::vector<RangeMeasurements>& measurements) {
  for (std::size_t s = 0; s < l.pairs.size(); ++s) {
    std::vector<RayPair>& pairs = l.pairs[s];
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                               [&](const RayPair& p) {
                                 const float r = measurements[s].range[p.ray];
                                 return !((p.model - p.measured).norm() < tolerance[s].at(r));
                               }),
                pairs.end());
  }
}

// A target's prior in the frame T0, in the units of pairs that weigh 1 (each of which stands for
// `information` per m^2 of residual), or nullopt.
std::optional<AlignmentPrior> priorInFrame(const RefineTarget& target, const Eigen::Isometry3d& T0,
                                           double information, const RefinerOptions& o) {
  if (o.prior_weight <= 0.0 || target.prior_information.isZero() || information <= 0.0)
    return std::nullopt;
  // World [translation, rotation] -> frame [rotation, translation].
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  M.block<3, 3>(0, 3) = T0.linear();
  M.block<3, 3>(3, 0) = T0.linear();
  AlignmentPrior prior;
  prior.T = T0.inverse() * target.T_prior;
  prior.information = (o.prior_weight / information) * M.transpose() * target.prior_information * M;
  return prior;
}

// Point-to-plane steps over `pairs` expressed in the frame T0 (the object's round-start pose).
IterativeAlignment alignInFrame(const FitPairs& fit, const Eigen::Isometry3d& T0,
                                const RefinerOptions& o, const AlignmentPrior* prior) {
  const std::vector<RayPair>& pairs = fit.pairs;
  const Eigen::Isometry3f T0_inv = T0.inverse().cast<float>();
  std::vector<Eigen::Vector3f> model, measured, normals;
  model.reserve(pairs.size()), measured.reserve(pairs.size()), normals.reserve(pairs.size());
  for (const RayPair& p : pairs) {
    model.push_back(T0_inv * p.model);
    measured.push_back(T0_inv * p.measured);
    normals.push_back(T0_inv.linear() * p.normal);
  }
  return alignPairs(model, measured, normals, NormalSide::kMoving, o.solver, o.steps,
                    o.step_tolerance, o.alignment, &fit.weight, prior);
}

float thresholdOfRound(const RefinerOptions& o, int round) {
  if (o.rounds <= 1) return o.max_dist_last;
  const float f = static_cast<float>(round) / static_cast<float>(o.rounds - 1);
  return o.max_dist_first * std::pow(o.max_dist_last / o.max_dist_first, f);
}

// An object's quality from its last round's pairs; its status from them and `degenerate`.
ObjectQuality qualityOf(const LastPairs& l, const std::vector<RangeTolerance>& tolerance,
                        const std::vector<RangeMeasurements>& measurements, const ObjectEstimate& e,
                        bool degenerate, const RefinerOptions& options) {
  ObjectQuality q = e.quality;  // keeps last_alignment
  double sq = 0.0, sq_of_threshold = 0.0, paired = 0.0, close = 0.0;
  const float last_threshold = thresholdOfRound(options, options.rounds - 1);
  const Eigen::Vector3d centre = e.T_world_object.translation();
  for (std::size_t s = 0; s < l.pairs.size(); ++s) {
    const double w = l.weight[s];  // rays of the base sampling a cast ray stands for
    for (const RayPair& p : l.pairs[s]) {
      const double r = (p.model - p.measured).norm();  // within the last round's threshold
      const double t = tolerance[s].at(measurements[s].range[p.ray]);
      paired += w;
      sq += w * r * r;
      sq_of_threshold += w * r * r / (t * t);
      close += r < last_threshold ? w : 0.0;
      if (!options.information) continue;
      const Eigen::Vector3d n = p.normal.cast<double>();
      Eigen::Matrix<double, 6, 1> J;
      J << n, (p.model.cast<double>() - centre).cross(n);
      q.information.noalias() += w * J * J.transpose();
    }
  }
  q.inliers = static_cast<int>(std::lround(paired));
  q.expected = static_cast<int>(std::lround(l.expected));
  q.inlier_ratio =
      q.expected > 0 ? std::min(1.0, static_cast<double>(q.inliers) / q.expected) : 0.0;
  q.close_ratio = options.noise_sigmas > 0.0f && q.expected > 0 ? std::min(1.0, close / q.expected)
                                                                : q.inlier_ratio;
  q.rmse = paired > 0.0 ? std::sqrt(sq / paired) : 0.0;
  q.rms_of_threshold = paired > 0.0 ? std::sqrt(sq_of_threshold / paired) : 0.0;
  if (q.expected == 0)
    q.status = RefineStatus::kNotVisible;
  else if (q.inliers < options.alignment.min_points)
    q.status = q.inlier_ratio < options.min_inlier_ratio ? RefineStatus::kFalseHypothesis
                                                         : RefineStatus::kTooFewPoints;
  else if (degenerate)
    q.status = RefineStatus::kDegenerate;
  else if (q.inlier_ratio < options.min_inlier_ratio)
    q.status = RefineStatus::kFalseHypothesis;
  else
    q.status = RefineStatus::kOk;
  return q;
}

}  // namespace

RangeTolerance noiseBand(const RangeMeasurements& m, float max_dist, const RefinerOptions& o) {
  return m.isDepthImage() ? RangeTolerance(m, max_dist, o.noise, o.noise_sigmas)
                          : RangeTolerance(max_dist);
}

RefineResult ObjectRefiner::refine(RaycastScene& scene, const std::vector<RefineTarget>& targets,
                                   const std::vector<RangeMeasurements>& measurements) const {
  const int n_obj = static_cast<int>(targets.size());
  RefineResult result;
  result.assignment.resize(measurements.size());
  for (std::size_t s = 0; s < measurements.size(); ++s)
    result.assignment[s].assign(measurements[s].size(), kNoNode);
  NodeGroups groups;
  std::vector<ObjectExtent> extents(n_obj);
  std::vector<MeshId> meshes(n_obj);
  for (int k = 0; k < n_obj; ++k) {
    groups.set(targets[k].node, k);
    meshes[k] = scene.instanceMesh(targets[k].node);
    extents[k].box = scene.meshBox(meshes[k]);
    extents[k].T_world_object = scene.instancePose(targets[k].node);
    result.objects.push_back({targets[k].node, extents[k].T_world_object, {}});
  }
  if (n_obj == 0) return result;

  std::vector<float> pull_radii(n_obj, options_.pull_radius);
  for (int k = 0; k < n_obj; ++k)
    if (targets[k].pull_radius >= 0.0f)
      pull_radii[k] = std::min(options_.pull_radius, targets[k].pull_radius);
  // Rays that can pair with an object pass through its box (ray pairs) or measure a point within
  // its pull radius of it (pulls): the rest are not cast.
  std::vector<float> margins(n_obj);
  for (int k = 0; k < n_obj; ++k)
    margins[k] = std::max(0.0f, std::min(options_.roi_margin, pull_radii[k]));
  std::vector<char> degenerate(n_obj, 0), done(n_obj, 0);
  std::vector<LastPairs> kept(n_obj);
  const float last_threshold = thresholdOfRound(options_, options_.rounds - 1);
  std::vector<RangeTolerance> last_tolerance;
  for (const RangeMeasurements& m : measurements)
    last_tolerance.push_back(noiseBand(m, last_threshold, options_));
  const bool early = options_.converged_step > 0.0;
  // Per set and object: the rays of the base sampling that reached it in the previous round.
  std::vector<std::vector<double>> on_object(measurements.size(), std::vector<double>(n_obj, -1.0));
  for (int round = 0; round < options_.rounds; ++round) {
    const float max_dist = thresholdOfRound(options_, round);
    const bool last = round + 1 == options_.rounds;
    // 1. Correspondences from every sensor, cast from the current estimates near the objects
    // still being refined.
    std::vector<FitPairs> pairs(n_obj);
    std::vector<LastPairs> found(n_obj);
    std::vector<double> first_information(n_obj, 1.0);
    for (std::size_t s = 0; s < measurements.size(); ++s) {
      const RangeMeasurements& m = measurements[s];
      const HitsLease lease = scratchHits(m.rays->width, m.rays->height);
      RayHits& hits = *lease;
      const bool coarse = (!last || !options_.full_resolution_last_round) &&
                          std::holds_alternative<PinholeModel>(m.model);
      RaySampling request;
      request.margins = &margins, request.skip = &done, request.on_object = &on_object[s];
      request.stride = coarse ? options_.ray_stride : 1;
      request.max_rays = coarse ? options_.max_rays_per_object : 0;
      const ObjectSampling sampling = sampleRaysNearObjects(m, extents, request);
      TileSet tiles = TileSet::sampled(*m.rays, sampling.regions,
                                       options_.jitter ? static_cast<unsigned>(round) : 0u);
      const RangeTolerance tolerance = noiseBand(m, max_dist, options_);
      tiles.keepRays(*m.rays, PairableRays(m, extents, margins, &done, tolerance));
      result.rays_cast += tiles.rayCount();
      PairingStats stats;
      if (early) stats.expected_within = &last_tolerance[s];  // an object may stop this round
      auto by_group = collectRayPairs(scene, m, tiles, groups, tolerance, hits, &stats);
      // Each pair's weight: its ray's information relative to one of the first set's (a single
      // set's pairs all weigh exactly 1).
      std::vector<float> weight(n_obj, 1.0f);
      const bool prior_scale = s == 0 && options_.prior_weight > 0.0;  // priorInFrame's units
      for (int k = 0; k < n_obj && (options_.weigh_by_noise || prior_scale); ++k) {
        const double information =
            rayInformation(m, extents[k], sampling.weight[k], options_.noise);
        if (s == 0) first_information[k] = information;
        if (options_.weigh_by_noise)
          weight[k] = static_cast<float>(information / first_information[k]);
      }
      for (int k = 0; k < n_obj; ++k) {
        if (done[k]) continue;
        appendAlignmentPairs(by_group[k], options_.noise_sigmas > 0.0f, max_dist, weight[k],
                             pairs[k]);
        found[k].pairs.push_back(std::move(by_group[k]));
        found[k].weight.push_back(sampling.weight[k]);
        found[k].expected += sampling.weight[k] * stats.expected[k];
        on_object[s][k] = sampling.weight[k] * stats.expected[k];
      }
      if (options_.pull_radius > 0.0f) {
        const UnexplainedPairing pulling{tolerance, options_.pull_front_margin, options_.roi_margin,
                                         options_.pull_radius, &pull_radii};
        const auto pulls =
            collectUnexplainedPairs(scene, m, tiles, hits, groups, extents, meshes, pulling);
        const bool point_to_point = round < options_.pull_point_to_point_rounds;
        for (int k = 0; k < n_obj; ++k)
          for (const RayPair& p : pulls[k])
            if (!done[k])
              point_to_point ? appendPointToPoint(p, weight[k], pairs[k])
                             : pairs[k].add(p, weight[k]);
      }
    }
    // No pair of the round reaches farther than this: larger updates are shortened (limitStep).
    const double step_limit = std::max(max_dist, options_.pull_radius);
    // 2. Per object, Umeyama steps over the round's pairs in the object's round-start frame.
    std::vector<double> moved(n_obj, 0.0);
    tbb::parallel_for(0, n_obj, [&](int k) {
      if (degenerate[k] || done[k]) return;
      const Eigen::Isometry3d T0 = extents[k].T_world_object;
      const auto prior = priorInFrame(targets[k], T0, first_information[k], options_);
      const IterativeAlignment a = alignInFrame(pairs[k], T0, options_, prior ? &*prior : nullptr);
      result.objects[k].quality.last_alignment = a.status;
      if (a.status == AlignmentStatus::kCollinear || a.status == AlignmentStatus::kPlanar)
        degenerate[k] = 1;
      if (a.steps > 0)
        extents[k].T_world_object = withoutSymmetricTwist(
            T0, T0 * limitStep(a.T, extents[k].box, step_limit), targets[k].symmetry);
      moved[k] = cornerShift(T0, extents[k].T_world_object, extents[k].box);
    });
    for (int k = 0; k < n_obj; ++k)
      scene.setInstancePose(targets[k].node, extents[k].T_world_object);
    scene.commit();
    // 3. An object's last round: the last one, or one that moved it less than converged_step.
    // Its quality comes from that round's pairs at the last round's tolerance.
    for (int k = 0; k < n_obj; ++k) {
      if (done[k] || !(last || (early && moved[k] < options_.converged_step))) continue;
      if (!last) keepWithin(found[k], last_tolerance, measurements);
      kept[k] = std::move(found[k]);
      done[k] = 1;
    }
    if (std::all_of(done.begin(), done.end(), [](char d) { return d != 0; })) break;
  }

  for (int k = 0; k < n_obj; ++k) {
    ObjectEstimate& e = result.objects[k];
    e.T_world_object = extents[k].T_world_object;
    e.quality = qualityOf(kept[k], last_tolerance, measurements, e, degenerate[k], options_);
    for (std::size_t s = 0; s < kept[k].pairs.size(); ++s)
      for (const RayPair& p : kept[k].pairs[s]) result.assignment[s][p.ray] = targets[k].node;
  }
  return result;
}

}  // namespace sgt
