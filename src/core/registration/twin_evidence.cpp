#include "scene_graph_tracker/registration/twin_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "scene_graph_tracker/registration/orientation_search.hpp"
#include "scene_graph_tracker/registration/ray_regions.hpp"

namespace sgt {
namespace {

// Mean distance from the surface samples moved by `turn` to the surface (each capped at `cap`).
double meanSurfaceDistance(const RaycastScene& scene, MeshId mesh,
                           const std::vector<Eigen::Vector3f>& samples,
                           const Eigen::Isometry3d& turn, float cap) {
  const Eigen::Isometry3f T = turn.cast<float>();
  double sum = 0.0;
  for (const Eigen::Vector3f& p : samples) {
    SurfacePoint sp;
    sum += scene.closestPoint(mesh, T * p, cap, sp) ? sp.distance : cap;
  }
  return samples.empty() ? 0.0 : sum / static_cast<double>(samples.size());
}

// log(N(e; 0, sigma) + outlier floor), without the Gaussian's constant (it cancels between poses
// measured by the same ray).
double rayLogLikelihood(float e, float sigma, float outlier_sigmas) {
  const double u = static_cast<double>(e) / sigma;
  return std::log(std::exp(-0.5 * u * u) + std::exp(-0.5 * outlier_sigmas * outlier_sigmas));
}

}  // namespace

std::vector<Eigen::Isometry3d> nearTwinTurns(const RaycastScene& scene, MeshId mesh,
                                             const ObjectClass& object, double max_mean_fraction) {
  constexpr double kSameTurnRad = 3.0 * M_PI / 180.0;  // finer than the sampled symmetries' step
  const std::vector<Eigen::Isometry3d> symmetries = object.symmetry.sampled();
  const std::vector<Eigen::Vector3f> samples = sampleSurface(*object.mesh, 500, 1).points;
  const float cap = static_cast<float>(0.1 * object.diameter);
  std::vector<Eigen::Isometry3d> twins;
  const auto turns =
      orientationCandidates(Eigen::Isometry3d::Identity(), object.box, cuboidRotations());
  for (std::size_t k = 1; k < turns.size(); ++k) {
    const Eigen::Matrix3d& R = turns[k].linear();
    if (angleUpToSymmetries(Eigen::Matrix3d::Identity(), R, symmetries) < kSameTurnRad) continue;
    if (std::any_of(twins.begin(), twins.end(), [&](const Eigen::Isometry3d& t) {
          return angleUpToSymmetries(t.linear(), R, symmetries) < kSameTurnRad;
        }))
      continue;
    if (meanSurfaceDistance(scene, mesh, samples, turns[k], cap) <=
        max_mean_fraction * object.diameter)
      twins.push_back(turns[k]);
  }
  return twins;
}

namespace {

// Log likelihood ratios of the measurements near `extents` under scene configurations 1..n-1
// against configuration 0, each set up by configure(k) before its cast; only rays that show
// `node` in configuration 0 or k count.
TwinEvidence compareConfigurations(RaycastScene& scene, NodeId node,
                                   const std::vector<ObjectExtent>& extents, std::size_t n,
                                   const std::function<void(std::size_t)>& configure,
                                   const std::vector<RangeMeasurements>& sets,
                                   const RangeNoise& noise, const TwinEvidenceOptions& options) {
  TwinEvidence out;
  out.log_ratio.assign(n, 0.0);
  out.z.assign(n, 0.0);
  std::vector<double> squares(n, 0.0);
  for (const RangeMeasurements& m : sets) {
    const TileSet tiles =
        TileSet::covering(*m.rays, raysNearObjects(m, extents, options.roi_margin));
    std::vector<HitsLease> leases;
    for (std::size_t k = 0; k < n; ++k) {
      leases.push_back(scratchHits(m.rays->width, m.rays->height));
      configure(k);
      scene.commit();
      scene.cast(*m.rays, m.T_world_sensor, *leases.back(), &tiles);
    }
    const RangeTolerance sigma(m, options.sigma_floor_m, noise, 1.0f);
    constexpr float kNoHit = std::numeric_limits<float>::infinity();
    tiles.forEachRay(*m.rays, [&](std::size_t i) {
      if (!m.valid(i)) return;
      const RayHits& own = *leases[0];
      const float z = m.range[i];
      const float s = sigma.at(z);
      const double l0 =
          rayLogLikelihood(own.hit(i) ? z - own.range[i] : kNoHit, s, options.outlier_sigmas);
      for (std::size_t k = 1; k < n; ++k) {
        const RayHits& h = *leases[k];
        if (h.node[i] != node && own.node[i] != node) continue;  // neither shows the object
        const float e = h.hit(i) ? z - h.range[i] : kNoHit;
        const double d = rayLogLikelihood(e, s, options.outlier_sigmas) - l0;
        out.log_ratio[k] += d;
        squares[k] += d * d;
      }
    });
  }
  for (std::size_t k = 1; k < n; ++k)
    if (squares[k] > 0.0) out.z[k] = out.log_ratio[k] / std::sqrt(squares[k]);
  return out;
}

}  // namespace

TwinEvidence twinLogLikelihoodRatios(RaycastScene& scene, NodeId node,
                                     const Eigen::AlignedBox3f& box,
                                     const std::vector<Eigen::Isometry3d>& poses,
                                     const std::vector<RangeMeasurements>& sets,
                                     const RangeNoise& noise, const TwinEvidenceOptions& options) {
  if (poses.size() < 2)
    return {std::vector<double>(poses.size(), 0.0), std::vector<double>(poses.size(), 0.0)};
  std::vector<ObjectExtent> extents;
  for (const Eigen::Isometry3d& T : poses) extents.push_back({T, box});
  TwinEvidence out = compareConfigurations(
      scene, node, extents, poses.size(),
      [&](std::size_t k) { scene.setInstancePose(node, poses[k]); }, sets, noise, options);
  scene.setInstancePose(node, poses[0]);
  scene.commit();
  return out;
}

double presenceScore(RaycastScene& scene, NodeId node, const Eigen::AlignedBox3f& box,
                     const std::vector<RangeMeasurements>& sets, const RangeNoise& noise,
                     const TwinEvidenceOptions& options) {
  const std::vector<ObjectExtent> extents{{scene.instancePose(node), box}};
  const TwinEvidence absent = compareConfigurations(
      scene, node, extents, 2, [&](std::size_t k) { scene.setInstanceEnabled(node, k == 0); }, sets,
      noise, options);
  scene.setInstanceEnabled(node, true);
  scene.commit();
  return -absent.z[1];
}

bool TwinBelief::update(const Eigen::Matrix3d& R, std::size_t twin, double z, double frame_cap,
                        double retain, double switch_log_odds) {
  if (Eigen::AngleAxisd(R_world_object.transpose() * R).angle() > kJumpRad)
    std::fill(log_odds.begin(), log_odds.end(), 0.0);
  R_world_object = R;
  if (twin >= log_odds.size()) return false;
  next = (twin + 1) % log_odds.size();
  const double beyond_noise = std::max(0.0, std::abs(z) - kNoiseScore);
  log_odds[twin] = retain * log_odds[twin] + std::copysign(std::min(beyond_noise, frame_cap), z);
  return log_odds[twin] > switch_log_odds;
}

double TwinBelief::confidence() const {
  double sum = 1.0;
  for (double l : log_odds) sum += std::exp(l);
  return 1.0 / sum;
}

}  // namespace sgt
