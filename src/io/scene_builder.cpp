// Builds a World from a validated Scene: bodies in file order (so BodyId{i} is Scene::bodies[i]),
// then joints, springs (spring joints) and standing loads. A definition the engine refuses is
// reported against its place in the file.
#include <linx/scene.hpp>

#include <fmt/format.h>

#include <cctype>
#include <stdexcept>
#include <string>
#include <string_view>

namespace linx {

namespace {

// The length of the field path that starts `what` ("limits.lower" of "limits.lower: must ..."):
// names, indices ("[2]") and dots, then ": "; 0 when it starts with none.
std::size_t fieldPathLength(std::string_view what) {
  const auto letter = [](char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
  };
  const auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  std::size_t i = 0;
  bool named = false;  // a name ends here (a '[' or a '.' may follow)
  while (i < what.size()) {
    const char c = what[i];
    if (letter(c) || (named && digit(c))) {
      named = true;
      ++i;
    } else if (c == '[' && named) {
      std::size_t j = i + 1;
      while (j < what.size() && digit(what[j])) ++j;
      if (j == i + 1 || j == what.size() || what[j] != ']') return 0;
      i = j + 1;
    } else if (c == '.' && named) {
      named = false;
      ++i;
    } else {
      break;
    }
  }
  return named && what.substr(i, 2) == ": " ? i : 0;
}

// The engine's refusal of the definition at `place` ("joints[2]"): its message starts with the
// field it is about when it knows it ("limits.lower: ..."), which joins the place's path
// ("joints[2].limits.lower: ...").
SceneError refused(const std::string& file, const std::string& place, const std::string& what) {
  const std::size_t length = fieldPathLength(what);
  if (length == 0) return SceneError(file, place, what);
  return SceneError(file, place + "." + what.substr(0, length), what.substr(length + 2));
}

// How far (m or rad) a coordinate may start outside its limits: rounding, not a modelling choice.
constexpr double kStartTolerance = 1e-6;
// How far a joint may start from what else it holds (a rod's length, a mimic's offset): what its
// first step closes without a kick that would stop the run.
constexpr double kStartError = 0.1;

// Where a scene gives coordinate c of the joint: "" (a joint of one coordinate: "limits" at its
// top level), "axes[c]." (a serial joint) or "NAME." ("position.").
std::string coordinateField(const SceneJoint& joint, std::size_t c) {
  const JointTypeInfo* type = findJointType(joint.type);
  if (!type || type->freeCoordinates(joint.def) <= 1) return "";
  if (type->usesAxes()) return fmt::format("axes[{}].", c);
  return c < type->coordinates.size() ? fmt::format("{}.", type->coordinates[c].name) : "";
}

// A joint must start where it holds its bodies: a coordinate outside its limits, a rope stretched
// past its length or a rod of another length than its points are apart would be pulled there in
// the first step, with all the energy that takes (the run would stop on a fault).
void checkStart(const Scene& scene, const World& world, std::size_t i) {
  const JointId id{static_cast<int>(i)};
  const double error = world.jointError(id);
  if (error <= kStartTolerance) return;  // the common case: nothing to look into
  const std::string place = fmt::format("joints[{}]", i);
  const auto& coordinates = scene.joints[i].def.coordinates;
  const JointCoordinates q = world.jointCoordinates(id);
  for (std::size_t c = 0; c < coordinates.size() && static_cast<Eigen::Index>(c) < q.size(); ++c) {
    if (!coordinates[c].limits) continue;
    const JointLimits& limits = *coordinates[c].limits;
    const double x = q[static_cast<Eigen::Index>(c)] + coordinates[c].reference;
    if (x >= limits.lower - kStartTolerance && x <= limits.upper + kStartTolerance) continue;
    throw SceneError(
        scene.file, fmt::format("{}.{}limits", place, coordinateField(scene.joints[i], c)),
        fmt::format("the joint starts at {:.6g}, outside its limits [{:.6g}, {:.6g}] (give "
                    "'initial' inside them, or place the bodies there)",
                    x, limits.lower, limits.upper));
  }
  if (error <= kStartError) return;
  throw SceneError(scene.file, place,
                   fmt::format("the joint starts {:.3g} (m or rad) away from what it holds where "
                               "the bodies are (a length, a limit or a relation not met at the "
                               "start): the first step would pull it there at once",
                               error));
}

// A body that starts faster than the fault bounds is a fault from the start: refused
// by the check, where the bounds are known, unless faults do not stop the run.
void checkStartSpeed(const Scene& scene, const World& world, std::size_t i) {
  const FaultSettings& faults = scene.settings.faults;
  if (!faults.stop) return;
  const Body& b = world.body(BodyId{static_cast<int>(i)});
  const double v = b.linearVelocity().stableNorm(), w = b.angularVelocity().stableNorm();
  const std::string place = fmt::format("bodies[{}]", i);
  if (v > faults.max_speed)
    throw SceneError(scene.file, place + ".linear_velocity",
                     fmt::format("the body starts at {:.6g} m/s, above faults.max_speed ({} m/s) "
                                 "(raise the bound to allow it)",
                                 v, faults.max_speed));
  if (w > faults.max_angular_speed)
    throw SceneError(scene.file, place + ".angular_velocity",
                     fmt::format("the body starts at {:.6g} rad/s, above faults.max_angular_speed "
                                 "({} rad/s) (raise the bound to allow it)",
                                 w, faults.max_angular_speed));
}

}  // namespace

World buildWorld(const Scene& scene) {
  World world(scene.settings);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    try {
      world.createBody(scene.bodies[i]);
    } catch (const std::invalid_argument& e) {
      throw refused(scene.file, fmt::format("bodies[{}]", i), e.what());
    }
  }
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    try {
      world.createJoint(scene.joints[i].type, scene.joints[i].def);
    } catch (const std::invalid_argument& e) {
      throw refused(scene.file, fmt::format("joints[{}]", i), e.what());
    }
  }
  for (std::size_t i = 0; i < scene.springs.size(); ++i) {
    try {
      world.createJoint(scene.springs[i].type, scene.springs[i].def);
    } catch (const std::invalid_argument& e) {
      throw refused(scene.file, fmt::format("springs[{}]", i), e.what());
    }
  }
  // Coordinates that start elsewhere than where the model was built: once every joint is made,
  // so that each moves its whole side of the mechanism.
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    const auto& coordinates = scene.joints[i].def.coordinates;
    for (std::size_t c = 0; c < coordinates.size(); ++c) {
      if (!coordinates[c].initial) continue;
      try {
        world.setJointCoordinate(JointId{static_cast<int>(i)}, static_cast<int>(c),
                                 *coordinates[c].initial);
      } catch (const std::invalid_argument& e) {
        throw refused(scene.file, fmt::format("joints[{}]", i), e.what());
      }
    }
  }
  for (std::size_t i = 0; i < scene.joints.size(); ++i) checkStart(scene, world, i);
  for (std::size_t i = 0; i < scene.actuators.size(); ++i) {
    try {
      world.createActuator(scene.actuators[i]);
    } catch (const std::invalid_argument& e) {
      throw refused(scene.file, fmt::format("actuators[{}]", i), e.what());
    }
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) checkStartSpeed(scene, world, i);
  for (const SceneLoad& load : scene.loads) {
    try {
      world.addLoad(load.def);
    } catch (const std::invalid_argument& e) {
      throw refused(scene.file, load.field, e.what());
    }
  }
  return world;
}

}  // namespace linx
