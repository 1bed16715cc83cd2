// Which of an object's near twins do the measurements support?
//
// A near twin is a turn of the object's box under which its surface almost maps onto itself: the
// material box turned by half a turn about its vertical axis differs only by its 3 mm latch and
// 2 mm lid grip, the multimeter by its knob and display. A keypoint detector confuses such twins
// consistently, and refinement (a local search) keeps whichever it was given: the twins explain
// nearly the same rays. The small features that tell them apart do show in the depth, a few rays
// per frame, each weakly. twinLogLikelihoodRatios() weighs them, the tracker accumulates the
// weights over frames (TwinBelief) and turns a track to its twin when the evidence has become
// strong, and reports how sure its orientation is until then.
#pragma once

#include <vector>

#include "scene_graph_tracker/scene/object_catalog.hpp"
#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/sensors/range_noise.hpp"

namespace sgt {

// The object's near twins: the turns of its box about the box centre (the 24 axis permutations,
// as the orientation search's) that are no declared symmetry (nor equivalent, up to the declared
// symmetries, to an earlier twin) and whose turned surface samples lie, in the mean, within
// `max_mean_fraction` of the diameter from the surface. `mesh` is the class's mesh in `scene`.
// Object frame: a track at T has the twin poses T * turn.
std::vector<Eigen::Isometry3d> nearTwinTurns(const RaycastScene& scene, MeshId mesh,
                                             const ObjectClass& object, double max_mean_fraction);

// Per-ray model of a measured range z against a predicted surface at range p: a Gaussian of the
// sensor's sigma at z (noise; at least sigma_floor_m) mixed with an outlier floor at
// outlier_sigmas, so that an unknown thing in front of the object or a missing return weighs
// little, whichever pose is right.
struct TwinEvidenceOptions {
  float sigma_floor_m = 0.001f;
  float outlier_sigmas = 3.0f;
  float roi_margin = 0.02f;  // object boxes grow by this much when picking the rays to cast
};

// For each of `poses` of the instance `node` (poses[0] first, its current one): the log likelihood
// of the measurements near it minus that of poses[0] (so [0] is 0), positive where a pose explains
// them better; and that sum over the rays divided by the root of the sum of its squared terms, a
// score that is about standard normal when the two poses differ by noise alone and grows with the
// root of the number of rays that agree on which is better, whatever the sensor's noise is taken
// to be (a depth camera noisier than configured inflates the ratio, not the score).
struct TwinEvidence {
  std::vector<double> log_ratio;
  std::vector<double> z;
};
// Every other instance of `scene` stays in place (occlusion as in refinement); the instance is
// left at poses[0].
TwinEvidence twinLogLikelihoodRatios(RaycastScene& scene, NodeId node,
                                     const Eigen::AlignedBox3f& box,
                                     const std::vector<Eigen::Isometry3d>& poses,
                                     const std::vector<RangeMeasurements>& sets,
                                     const RangeNoise& noise,
                                     const TwinEvidenceOptions& options = {});

// How much better the measurements near the instance `node` (at its pose in `scene`) are
// explained with it than without it (the scene behind it: the map, the other instances): the
// score of TwinEvidence for the scene with it against the scene without it. Near zero where
// something else explains the same rays as well (a second model of one object, a flat model
// laid on a bench within the noise), negative where its surface contradicts them.
double presenceScore(RaycastScene& scene, NodeId node, const Eigen::AlignedBox3f& box,
                     const std::vector<RangeMeasurements>& sets, const RangeNoise& noise,
                     const TwinEvidenceOptions& options = {});

// A track's accumulated evidence for each of its twins against its own orientation (log odds).
// Each frame counts its score (TwinEvidence::z) beyond kNoiseScore, clipped to +-frame_cap: a
// frame's rays are not independent (a depth camera's errors are correlated over an object), so
// no one frame decides, and a far object's ratio, a few nats either way with scores within about
// one of zero (the simulated suite's material box at 2.3 m: -1.8 to 2.5), counts little. Older
// evidence fades by `retain` per update, so an object turned by a hand later is followed.
struct TwinBelief {
  std::vector<double> log_odds;  // one per twin
  // The track's rotation at the last update: evidence is about the twins of that orientation, so a
  // track turned since by more than kJumpRad (an orientation search, a restart from a detection;
  // twins lie 90 deg or more apart) starts afresh.
  Eigen::Matrix3d R_world_object = Eigen::Matrix3d::Identity();
  static constexpr double kJumpRad = M_PI / 4;
  static constexpr double kNoiseScore = 1.0;

  std::size_t next = 0;  // the twin the next test weighs (one per test: a cube has 23)

  // Folds in one frame's score z of twin `twin` against the track's rotation R_world_object, and
  // moves `next` on. Returns whether its log odds now exceed switch_log_odds (the track should turn
  // to it).
  bool update(const Eigen::Matrix3d& R_world_object, std::size_t twin, double z, double frame_cap,
              double retain, double switch_log_odds);
  // The probability of the track's own orientation against its twins (uniform prior): 1 / (1 +
  // sum exp(log odds)); 1 without twins.
  double confidence() const;
  void reset(std::size_t twins) { log_odds.assign(twins, 0.0), next = 0; }
};

}  // namespace sgt
