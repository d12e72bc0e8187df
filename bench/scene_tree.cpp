#include "scene_tree.hpp"

#include "engine.hpp"

#include <algorithm>
#include <string>

namespace bench {

bool parallel(const Vec3& a, const Vec3& b) {
  return a.cross(b).norm() <= 1e-9 * a.norm() * b.norm();
}

int treeNode(const Scene& scene, int body) {
  return body < 0 || scene.bodies[static_cast<std::size_t>(body)].is_static ? kWorld : body;
}

SceneTree buildSceneTree(const Scene& scene, bool static_roots) {
  const int n = static_cast<int>(scene.bodies.size());
  const auto un = static_cast<std::size_t>(n);
  SceneTree t;
  t.parent.assign(un, kWorld);
  t.joint.assign(un, -1);
  t.flipped.assign(un, false);
  t.free_root.assign(un, false);
  t.children.resize(un);

  // Incidence lists (world at index n), in joint order.
  std::vector<std::vector<int>> incident(un + 1);
  const auto slot = [n](int v) { return static_cast<std::size_t>(v == kWorld ? n : v); };
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const Joint& jt = scene.joints[j];
    if (jt.body1 < kWorld || jt.body1 >= n || jt.body2 < kWorld || jt.body2 >= n)
      throw Unsupported("a joint refers to a body that does not exist");
    const int a = treeNode(scene, jt.body1), b = treeNode(scene, jt.body2);
    if (a == b) {
      if (a == kWorld) continue;  // between the world and static bodies: no effect
      throw Unsupported("a joint joins body " + std::to_string(a) + " to itself");
    }
    incident[slot(a)].push_back(static_cast<int>(j));
    incident[slot(b)].push_back(static_cast<int>(j));
  }

  std::vector<bool> placed(un + 1, false), used(scene.joints.size(), false);
  std::vector<int> queue;
  const auto search = [&](int start) {
    queue.assign(1, start);
    placed[slot(start)] = true;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int u = queue[q];
      for (int j : incident[slot(u)]) {
        if (used[static_cast<std::size_t>(j)]) continue;
        used[static_cast<std::size_t>(j)] = true;
        const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
        const int a = treeNode(scene, jt.body1), b = treeNode(scene, jt.body2);
        const int v = a == u ? b : a;
        if (placed[slot(v)]) {
          t.closures.push_back(j);
          continue;
        }
        placed[slot(v)] = true;
        const auto vi = static_cast<std::size_t>(v);
        t.parent[vi] = u;
        t.joint[vi] = j;
        t.flipped[vi] = v == a;  // the child is body1
        if (u == kWorld) {
          t.roots.push_back(v);
        } else {
          t.children[static_cast<std::size_t>(u)].push_back(v);
        }
        queue.push_back(v);
      }
    }
  };
  search(kWorld);
  for (int i = 0; i < n; ++i) {
    if (scene.bodies[static_cast<std::size_t>(i)].is_static) {
      if (static_roots) t.roots.push_back(i);  // jointless child of the world
      continue;
    }
    if (placed[slot(i)]) continue;
    t.free_root[static_cast<std::size_t>(i)] = true;
    t.roots.push_back(i);
    search(i);
  }
  std::sort(t.closures.begin(), t.closures.end());
  return t;
}

bool rotationKeptAbout(const Scene& scene, const SceneTree& t, int a, int b, const Vec3& axis) {
  std::vector<int> up_a;
  for (int v = a; v != kWorld; v = t.parent[static_cast<std::size_t>(v)]) up_a.push_back(v);
  int lca = kWorld;
  std::vector<int> path;
  for (int v = b; v != kWorld; v = t.parent[static_cast<std::size_t>(v)]) {
    if (std::find(up_a.begin(), up_a.end(), v) != up_a.end()) {
      lca = v;
      break;
    }
    path.push_back(v);
  }
  for (int v : up_a) {
    if (v == lca) break;
    path.push_back(v);
  }
  for (int v : path) {
    const auto vi = static_cast<std::size_t>(v);
    if (t.free_root[vi]) return false;
    const Joint& jt = scene.joints[static_cast<std::size_t>(t.joint[vi])];
    switch (jt.kind) {
      case Joint::Kind::Hinge:
        if (!parallel(jt.axis, axis)) return false;
        break;
      case Joint::Kind::Slider:
      case Joint::Kind::Fixed:
        break;
      case Joint::Kind::Ball:
        return false;
    }
  }
  return true;
}

}  // namespace bench
