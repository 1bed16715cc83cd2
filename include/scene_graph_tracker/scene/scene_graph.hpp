// The scene graph: named nodes with a class, a parent and a local transform T_parent_node.
// The root (id kWorldNode, the map frame) always exists. World transforms compose up the tree.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "scene_graph_tracker/scene/node_id.hpp"

namespace sgt {

struct SceneNode {
  NodeId id = kWorldNode;
  std::string name;
  std::string class_name;  // empty for frames and the static map
  NodeId parent = kWorldNode;
  Eigen::Isometry3d T_parent_node = Eigen::Isometry3d::Identity();
  std::vector<NodeId> children;
};

class SceneGraph {
 public:
  explicit SceneGraph(const std::string& world_name = "map");

  NodeId add(const std::string& name, const std::string& class_name, NodeId parent,
             const Eigen::Isometry3d& T_parent_node);
  // Removes a node; its children move up to its parent and keep their world pose.
  void remove(NodeId id);
  bool contains(NodeId id) const { return nodes_.count(id) > 0; }
  const SceneNode& node(NodeId id) const;
  // The node with this name, or kNoNode.
  NodeId find(const std::string& name) const;
  std::size_t size() const { return nodes_.size(); }

  Eigen::Isometry3d worldTransform(NodeId id) const;  // T_world_node
  void setLocalTransform(NodeId id, const Eigen::Isometry3d& T_parent_node);
  void setWorldTransform(NodeId id, const Eigen::Isometry3d& T_world_node);
  // Moves `id` under `new_parent` keeping its world pose:
  // T_newparent_node = T_world_newparent^-1 * T_world_node. Refuses cycles.
  void reparent(NodeId id, NodeId new_parent);
  bool isAncestor(NodeId ancestor, NodeId id) const;

  // `id` and all nodes below it (depth first), e.g. to update their ray-casting instances.
  std::vector<NodeId> subtree(NodeId id) const;
  std::vector<NodeId> ids() const;
  void forEach(const std::function<void(const SceneNode&)>& f) const;

 private:
  SceneNode& mutableNode(NodeId id);
  std::map<NodeId, SceneNode> nodes_;
  NodeId next_id_ = 1;
};

}  // namespace sgt
