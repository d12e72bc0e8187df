#include "io/joint_warnings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>

namespace linx::io {

namespace {

// Within these, two anchors are one point and two axes one direction.
constexpr double kSamePoint = 1e-6;  // (m)
constexpr double kSameAngle = 1e-6;  // (rad)
constexpr std::size_t kNamed = 3;    // repeats named in a warning
// More copies of one joint than this are refused: the exact solver solves their redundant rows
// as one dense block, at a cost growing with the cube of their number (100 hinges: 0.24 s a
// step, 300: past a minute for 20 steps), so a small scene could keep a run busy for hours.
constexpr std::size_t kMaxRepeats = 16;

bool sameJoint(const SceneJoint& a, const SceneJoint& b) {
  const JointDef &p = a.def, &q = b.def;
  if (a.type != b.type || p.local != q.local) return false;
  // A joint that ties joints (a mimic) is the same only when it ties the same two.
  if (p.leader != q.leader || p.follower != q.follower) return false;
  const bool same_order = p.body1 == q.body1 && p.body2 == q.body2;
  const bool swapped = p.body1 == q.body2 && p.body2 == q.body1;
  // A local frame belongs to its body: only the same order compares.
  if (!(same_order || (swapped && !p.local))) return false;
  if (p.anchor.has_value() != q.anchor.has_value()) return false;
  if (p.anchor && (*p.anchor - *q.anchor).norm() > kSamePoint) return false;
  const Vec3 u = p.axis.normalized(), v = q.axis.normalized();
  return u.cross(v).norm() <= kSameAngle;
}

std::string bodyName(const Scene& scene, BodyId id) {
  return id.isWorld() ? std::string("world")
                      : "'" + scene.bodies[static_cast<std::size_t>(id.index)].name + "'";
}

/// What a joint joins: "between bodies 'a' and 'b'", or for one that ties joints (a mimic),
/// "tying joints 'x' and 'y'" (its bodies are the world until the world is built).
std::string joins(const Scene& scene, const JointDef& d) {
  const auto jointName = [&](JointId id) {
    return "'" + scene.joints[static_cast<std::size_t>(id.index)].def.name + "'";
  };
  if (d.leader && d.follower)
    return fmt::format("tying joints {} and {}", jointName(*d.leader), jointName(*d.follower));
  return fmt::format("between bodies {} and {}", bodyName(scene, d.body1),
                     bodyName(scene, d.body2));
}

}  // namespace

std::vector<std::string> redundantJointWarnings(const Scene& scene) {
  std::vector<std::string> warnings;
  const std::size_t n = scene.joints.size();
  std::vector<bool> grouped(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (grouped[i]) continue;
    std::vector<std::size_t> repeats;
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!grouped[j] && sameJoint(scene.joints[i], scene.joints[j])) {
        grouped[j] = true;
        repeats.push_back(j);
      }
    }
    if (repeats.empty()) continue;
    const JointDef& d = scene.joints[i].def;
    if (repeats.size() > kMaxRepeats)
      throw SceneError(
          scene.file, fmt::format("joints[{}]", i),
          fmt::format("'{}' repeated by {} more joints, above the limit of {}: the same {} {} "
                      "at the same anchor and axis, whose redundant rows the exact solver solves "
                      "densely at a cost growing with the cube of their number; keep one",
                      d.name, repeats.size(), kMaxRepeats, scene.joints[i].type, joins(scene, d)));
    const auto named = [&](std::size_t k) {
      return fmt::format("joints[{}] ({})", k, scene.joints[k].def.name);
    };
    std::string list;
    for (std::size_t k = 0; k < std::min(repeats.size(), kNamed); ++k)
      list += (k ? ", " : "") + named(repeats[k]);
    if (repeats.size() > kNamed) list += ", ...";
    warnings.push_back(fmt::format(
        "{}: {} repeated by {} more ({}): the same {} {} at the same anchor and axis; their rows "
        "are redundant, which the exact solver solves densely at a cost growing with the cube of "
        "their number; keep one",
        scene.file, named(i), repeats.size(), list, scene.joints[i].type, joins(scene, d)));
  }
  return warnings;
}

std::vector<std::string> idleJointWarnings(const Scene& scene) {
  const auto still = [&](BodyId id) {
    if (id.isWorld()) return true;
    const BodyDef& b = scene.bodies[static_cast<std::size_t>(id.index)];
    return b.is_static && !b.kinematic;
  };
  std::vector<std::string> warnings;
  const auto check = [&](const std::vector<SceneJoint>& joints, std::string_view list) {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const JointDef& d = joints[i].def;
      if (d.leader || !still(d.body1) || !still(d.body2)) continue;  // a mimic ties joints
      const auto name = [&](BodyId id) {
        return id.isWorld() ? std::string("the world") : bodyName(scene, id);
      };
      warnings.push_back(fmt::format(
          "{}: {}[{}] ({}): joins {} and {}, neither of which moves (static bodies, the world): "
          "it never acts",
          scene.file, list, i, d.name, name(d.body1), name(d.body2)));
    }
  };
  check(scene.joints, "joints");
  check(scene.springs, "springs");
  return warnings;
}

std::vector<std::string> jointWarnings(const Scene& scene) {
  std::vector<std::string> warnings = redundantJointWarnings(scene);
  for (std::string& w : idleJointWarnings(scene)) warnings.push_back(std::move(w));
  return warnings;
}

}  // namespace linx::io
