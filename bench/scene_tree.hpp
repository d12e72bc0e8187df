// A bench scene as kinematic trees, for the reduced-coordinate peers (MuJoCo, DART): a spanning
// forest of the joint graph, rooted at the world, and the joints that close loops.
#pragma once

#include "scene.hpp"

#include <vector>

namespace bench {

/// The world as a tree node.
constexpr int kWorld = -1;

/// The scene as kinematic trees. Node indices are scene body indices; kWorld is the world.
struct SceneTree {
  std::vector<int> parent;      ///< kWorld for roots (and static bodies)
  std::vector<int> joint;       ///< scene joint of the edge to the parent; -1: none
  std::vector<bool> flipped;    ///< the edge runs from body2 (parent) to body1 (child)
  std::vector<bool> free_root;  ///< dynamic root without a joint: gets a free joint
  std::vector<std::vector<int>> children;
  std::vector<int> roots;     ///< children of the world, in order
  std::vector<int> closures;  ///< scene joints that close loops, ascending
};

/// A joint end as a tree node: the world and static bodies are the world.
int treeNode(const Scene& scene, int body);

/// The spanning forest, breadth first from the world, then from each dynamic body not reached
/// (a free root). `static_roots`: static bodies are listed among the roots too, as jointless
/// children of the world. Throws Unsupported for a joint to a body that does not exist or from a
/// body to itself.
SceneTree buildSceneTree(const Scene& scene, bool static_roots);

/// Whether the tree paths between the two nodes keep their relative rotation about `axis` only:
/// every joint on them is a hinge parallel to axis, a slider or a fixed joint, and no path runs
/// through a free root.
bool rotationKeptAbout(const Scene& scene, const SceneTree& t, int a, int b, const Vec3& axis);

/// a and b are parallel (or opposite), to 1e-9.
bool parallel(const Vec3& a, const Vec3& b);

}  // namespace bench
