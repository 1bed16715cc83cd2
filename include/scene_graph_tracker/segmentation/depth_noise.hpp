// A depth camera's noise, measured in every frame on the static map, where the surface is known.
//
// The thresholds that decide whether a measurement lies on a predicted surface (refinement,
// pre-segmentation) scale with the camera's noise, and that noise differs between cameras, with
// the light and the surface. A fixed setting that is too small for the camera makes a far object's
// correct returns look like outliers. The map is most of what a depth image sees, so its
// residuals give the noise of this camera now.
#pragma once

#include <optional>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

struct DepthNoiseOptions {
  int stride = 4;  // every stride-th pixel in x and y is cast
  // Residuals within this many sigmas of the configured noise count (the window does not follow
  // the measurement: a map that misses a surface by centimetres, or a camera pose that is off,
  // would widen it without end) ...
  float window_sigmas = 10.0f;
  float min_window = 0.02f;  // ... and within this, whatever the noise (m)
  int min_rays = 500;        // fewer residuals measure nothing
};

// The sigma at 1 m of depth noise growing with range squared, sigma(p) = s * p^2: 1.4826 x the
// median of |measured - predicted range| / p^2 over the rays of the depth image `m` that hit the
// static map of `scene` within max(min_window, window_sigmas * configured_sigma_at_1m * p^2) of
// its surface (p: the predicted range). The median ignores what the map does not hold (unknown
// things, mixed pixels at edges) while it is less than half of the residuals; what the window
// cuts off bounds the result. It measures the camera's noise together with the error of its pose
// against the map. Nothing when `m` is no depth image, the scene has no static map, or fewer
// than min_rays residuals count.
std::optional<float> measureDepthSigmaAt1m(const RaycastScene& scene, const RangeMeasurements& m,
                                           float configured_sigma_at_1m,
                                           const DepthNoiseOptions& o = {});

}  // namespace sgt
