#include "scene_graph_tracker/scene/scene_graph.hpp"

#include <algorithm>
#include <stdexcept>

namespace sgt {

SceneGraph::SceneGraph(const std::string& world_name) {
  SceneNode root;
  root.id = kWorldNode;
  root.name = world_name;
  root.parent = kWorldNode;
  nodes_.emplace(kWorldNode, root);
}

SceneNode& SceneGraph::mutableNode(NodeId id) {
  const auto it = nodes_.find(id);
  if (it == nodes_.end()) throw std::out_of_range("scene graph: no node " + std::to_string(id));
  return it->second;
}

const SceneNode& SceneGraph::node(NodeId id) const {
  return const_cast<SceneGraph*>(this)->mutableNode(id);
}

NodeId SceneGraph::find(const std::string& name) const {
  for (const auto& [id, n] : nodes_)
    if (n.name == name) return id;
  return kNoNode;
}

NodeId SceneGraph::add(const std::string& name, const std::string& class_name, NodeId parent,
                       const Eigen::Isometry3d& T_parent_node) {
  if (!T_parent_node.matrix().allFinite())
    throw std::invalid_argument("scene graph: non-finite transform for '" + name + "'");
  SceneNode& p = mutableNode(parent);
  SceneNode n;
  n.id = next_id_++;
  n.name = name;
  n.class_name = class_name;
  n.parent = parent;
  n.T_parent_node = T_parent_node;
  p.children.push_back(n.id);
  nodes_.emplace(n.id, n);
  return n.id;
}

void SceneGraph::remove(NodeId id) {
  if (id == kWorldNode)
    throw std::invalid_argument("scene graph: the world node cannot be removed");
  const SceneNode n = node(id);
  for (NodeId child : n.children) reparent(child, n.parent);
  auto& siblings = mutableNode(n.parent).children;
  siblings.erase(std::remove(siblings.begin(), siblings.end(), id), siblings.end());
  nodes_.erase(id);
}

Eigen::Isometry3d SceneGraph::worldTransform(NodeId id) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  while (id != kWorldNode) {
    const SceneNode& n = node(id);
    T = n.T_parent_node * T;
    id = n.parent;
  }
  return T;
}

void SceneGraph::setLocalTransform(NodeId id, const Eigen::Isometry3d& T_parent_node) {
  if (id == kWorldNode) throw std::invalid_argument("scene graph: the world node does not move");
  if (!T_parent_node.matrix().allFinite())
    throw std::invalid_argument("scene graph: non-finite transform for node " + std::to_string(id));
  mutableNode(id).T_parent_node = T_parent_node;
}

void SceneGraph::setWorldTransform(NodeId id, const Eigen::Isometry3d& T_world_node) {
  const NodeId parent = node(id).parent;
  setLocalTransform(id, worldTransform(parent).inverse() * T_world_node);
}

bool SceneGraph::isAncestor(NodeId ancestor, NodeId id) const {
  while (id != kWorldNode) {
    id = node(id).parent;
    if (id == ancestor) return true;
  }
  return false;
}

void SceneGraph::reparent(NodeId id, NodeId new_parent) {
  if (id == kWorldNode) throw std::invalid_argument("scene graph: the world node has no parent");
  if (id == new_parent || isAncestor(id, new_parent))
    throw std::invalid_argument("scene graph: re-parenting node " + std::to_string(id) + " under " +
                                std::to_string(new_parent) + " would make a cycle");
  const Eigen::Isometry3d T_world_node = worldTransform(id);
  const Eigen::Isometry3d T_world_parent = worldTransform(new_parent);
  SceneNode& n = mutableNode(id);
  auto& old_siblings = mutableNode(n.parent).children;
  old_siblings.erase(std::remove(old_siblings.begin(), old_siblings.end(), id), old_siblings.end());
  n.parent = new_parent;
  n.T_parent_node = T_world_parent.inverse() * T_world_node;
  mutableNode(new_parent).children.push_back(id);
}

std::vector<NodeId> SceneGraph::subtree(NodeId id) const {
  std::vector<NodeId> out{id};
  for (std::size_t i = 0; i < out.size(); ++i)
    for (NodeId c : node(out[i]).children) out.push_back(c);
  return out;
}

std::vector<NodeId> SceneGraph::ids() const {
  std::vector<NodeId> out;
  for (const auto& kv : nodes_) out.push_back(kv.first);
  return out;
}

void SceneGraph::forEach(const std::function<void(const SceneNode&)>& f) const {
  for (const auto& kv : nodes_) f(kv.second);
}

}  // namespace sgt
