// Hypotheses that reach the tracker some frames after the image they were detected on: what a
// tracker that never waits for its detector gets (hypothesis_max_wait 0, a detector slower than
// the camera's frame period). `evaluate --detector-delay-frames N` replays that offline. Each
// frame's batch is kept with the odometry of its image and comes out N frames later, moved into
// the base frame of the frame that receives it (as FrameAssembler moves a late array live).
#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <utility>
#include <vector>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

namespace sgt::detection {

class DelayedHypotheses {
 public:
  explicit DelayedHypotheses(int frames) : frames_(frames < 0 ? 0 : frames) {}
  // This frame's detections (base frame at T_odom_base) in; the batch detected `frames` frames
  // ago out, in this frame's base frame (none during the first `frames` frames).
  std::vector<PoseHypothesis> pass(std::vector<PoseHypothesis> detected,
                                   const Eigen::Isometry3d& T_odom_base);

 private:
  int frames_;
  std::deque<std::pair<Eigen::Isometry3d, std::vector<PoseHypothesis>>> pending_;
};

}  // namespace sgt::detection
