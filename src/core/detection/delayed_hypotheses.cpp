#include "scene_graph_tracker/detection/delayed_hypotheses.hpp"

namespace sgt::detection {

std::vector<PoseHypothesis> DelayedHypotheses::pass(std::vector<PoseHypothesis> detected,
                                                    const Eigen::Isometry3d& T_odom_base) {
  if (frames_ <= 0) return detected;  // untouched: not even moved by an identity's rounding
  pending_.emplace_back(T_odom_base, std::move(detected));
  if (pending_.size() <= static_cast<std::size_t>(frames_)) return {};
  auto [T_odom_then, due] = std::move(pending_.front());
  pending_.pop_front();
  const Eigen::Isometry3d T_now_then = T_odom_base.inverse() * T_odom_then;
  for (PoseHypothesis& h : due) h.T_base_object = T_now_then * h.T_base_object;
  return due;
}

}  // namespace sgt::detection
