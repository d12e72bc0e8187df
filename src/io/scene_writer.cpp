// Writes a Scene as a JSON scene file (docs/scene-format.md) that scene_reader.cpp reads back to
// the same scene: every number is written so that it parses to the same bits, and values the
// reader derives (normalized directions and quaternions, symmetrized inertias, mass properties
// completed from densities) are written in a form the reader turns back into what was stored.
// What no scene file can hold is refused with the field's path rather than written differently.
#include <linx/mass_properties.hpp>
#include <linx/scene.hpp>
#include <linx/shape.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>

#include "io/unit_vectors.hpp"
#include "schema/describe.hpp"

namespace linx {

namespace {

using json = nlohmann::ordered_json;

std::string childPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : fmt::format("{}.{}", parent, key);
}

std::string itemPath(const std::string& parent, std::size_t index) {
  return fmt::format("{}[{}]", parent, index);
}

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw std::runtime_error(
      fmt::format("{}: cannot be written as a scene file: {}", field, problem));
}

// Equal to the bit (0.0 and -0.0 differ): a value left out must read back as the default.
bool same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

template <int N>
bool same(const Eigen::Matrix<double, N, 1>& a, const Eigen::Matrix<double, N, 1>& b) {
  for (int i = 0; i < N; ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}

bool same(const Quat& a, const Quat& b) {
  return same(Eigen::Vector4d(a.coeffs()), Eigen::Vector4d(b.coeffs()));
}

// A number as JSON (nlohmann prints the shortest text that parses to the same bits).
json number(double x, const std::string& field) {
  if (!std::isfinite(x)) fail(field, fmt::format("{} is not a finite number", x));
  return x;
}

template <int N>
json numbers(const Eigen::Matrix<double, N, 1>& v, const std::string& field) {
  json out = json::array();
  for (int i = 0; i < N; ++i)
    out.push_back(number(v[i], itemPath(field, static_cast<std::size_t>(i))));
  return out;
}

json vec3(const Vec3& v, const std::string& field) {
  return numbers<3>(v, field);
}

// What the reader makes of a direction or a quaternion (io::readNormalized).
template <int N>
Eigen::Matrix<double, N, 1> readerNormalized(const Eigen::Matrix<double, N, 1>& v) {
  return io::readNormalized<N>(v);
}

// A vector that the reader normalizes to exactly `v`: `v` itself when its length is 1 to the bit.
// Else the first found among `v` scaled by 1 + m / 1024 (m = 0, 1, ...), each component moved by
// at most one unit in the last place: rounding makes some of them divide back to `v` exactly.
template <int N>
Eigen::Matrix<double, N, 1> normalizedPreimage(const Eigen::Matrix<double, N, 1>& v,
                                               const std::string& field) {
  using Vector = Eigen::Matrix<double, N, 1>;
  if (!v.allFinite() || !(v.stableNorm() > 0)) fail(field, "must be a finite non-zero vector");
  if (same<N>(readerNormalized<N>(v), v)) return v;
  constexpr int kScales = 4096;
  int nudges = 1;  // each component down, kept or up
  for (int i = 0; i < N; ++i) nudges *= 3;
  for (int m = 0; m < kScales; ++m) {
    const Vector scaled = v * (1.0 + m / 1024.0);
    for (int code = 0; code < nudges; ++code) {
      Vector w = scaled;
      for (int i = 0, rest = code; i < N; ++i, rest /= 3)
        if (rest % 3 != 1) w[i] = std::nextafter(w[i], rest % 3 == 0 ? -kInfinity : kInfinity);
      if (same<N>(readerNormalized<N>(w), v)) return w;
    }
  }
  fail(field, "no vector reads back to it to the bit (the reader normalizes it)");
}

json direction(const Vec3& v, const std::string& field) {
  return vec3(normalizedPreimage<3>(v, field), field);
}

// [w, x, y, z]
json orientation(const Quat& q, const std::string& field) {
  const Eigen::Vector4d wxyz(q.w(), q.x(), q.y(), q.z());
  return numbers<4>(normalizedPreimage<4>(wxyz, field), field);
}

// The reader symmetrizes a 3x3 inertia, and so does Body: written symmetrized, it reads back to
// the matrix the body is made with.
json inertia(const Mat3& m, const std::string& field) {
  const Mat3 symmetric = 0.5 * (m + m.transpose());
  json rows = json::array();
  for (int r = 0; r < 3; ++r)
    rows.push_back(
        vec3(symmetric.row(r).transpose(), itemPath(field, static_cast<std::size_t>(r))));
  return rows;
}

bool isConstant(const Signal& s) {
  return s.times.empty();
}

// A number, or a table {"times": [...], "values": [...]} (a table read from a CSV file too).
json signal(const Signal& s, const std::string& field) {
  if (isConstant(s)) {
    if (s.values.size() != 1) fail(field, "a constant signal holds one value");
    return number(s.values[0], field);
  }
  if (s.values.size() != s.times.size())
    fail(field, fmt::format("{} values for {} times", s.values.size(), s.times.size()));
  json times = json::array(), values = json::array();
  for (std::size_t i = 0; i < s.times.size(); ++i) {
    times.push_back(number(s.times[i], itemPath(childPath(field, "times"), i)));
    values.push_back(number(s.values[i], itemPath(childPath(field, "values"), i)));
  }
  return json{{"times", std::move(times)}, {"values", std::move(values)}};
}

// [x, y, z], each component a number or a table.
json vectorSignal(const VectorSignal& v, const std::string& field) {
  json out = json::array();
  for (std::size_t k = 0; k < 3; ++k) out.push_back(signal(v.components[k], itemPath(field, k)));
  return out;
}

// Sets `key` when `value` differs (to the bit) from what the reader takes when it is left out.
void putIfChanged(json& j, std::string_view key, double value, double fallback,
                  const std::string& parent) {
  if (!same(value, fallback)) j[std::string(key)] = number(value, childPath(parent, key));
}

void putIfChanged(json& j, std::string_view key, int value, int fallback) {
  if (value != fallback) j[std::string(key)] = value;
}

void putIfChanged(json& j, std::string_view key, bool value, bool fallback) {
  if (value != fallback) j[std::string(key)] = value;
}

void putIfChanged(json& j, std::string_view key, const Vec3& value, const Vec3& fallback,
                  const std::string& parent) {
  if (!same<3>(value, fallback)) j[std::string(key)] = vec3(value, childPath(parent, key));
}

// A section of settings, left out when it holds nothing but defaults.
void putSection(json& root, std::string_view key, json section) {
  if (!section.empty()) root[std::string(key)] = std::move(section);
}

// --- Described records (src/schema/describe.hpp) ------------------------------------------------

template <class R>
json record(const R& r, const std::string& path);

// Every field of a record that holds a value, as the reader reads it back.
class FieldWriter {
 public:
  FieldWriter(json& out, const std::string& path) : out_(out), path_(path) {}

  void field(const double& x, const schema::FieldInfo& info) {
    if (!(info.infinite && std::isinf(x))) put(info, number(x, path(info)));  // inf: unbounded
  }
  void field(const int& x, const schema::FieldInfo& info) { put(info, x); }
  void field(const bool& x, const schema::FieldInfo& info) { put(info, x); }
  void field(const Signal& x, const schema::FieldInfo& info) { put(info, signal(x, path(info))); }
  void field(const std::optional<double>& x, const schema::FieldInfo& info) {
    if (x) field(*x, info);
  }
  void field(const std::optional<Vec3>& x, const schema::FieldInfo& info) {
    if (x) put(info, info.direction ? direction(*x, path(info)) : vec3(*x, path(info)));
  }
  void field(const std::optional<Signal>& x, const schema::FieldInfo& info) {
    if (x) field(*x, info);
  }
  template <class R>
  requires schema::kIsRecord<R>
  void field(const std::optional<R>& x, const schema::FieldInfo& info) {
    if (x) put(info, record(*x, path(info)));
  }
  template <class E>
  requires std::is_enum_v<E>
  void field(const E& x, const schema::FieldInfo& info) {
    put(info, std::string(info.choices[static_cast<std::size_t>(x)]));
  }

 private:
  std::string path(const schema::FieldInfo& info) const { return childPath(path_, info.name); }
  void put(const schema::FieldInfo& info, json value) {
    out_[std::string(info.name)] = std::move(value);
  }

  json& out_;
  const std::string& path_;
};

// All the fields of `r`, with nothing but what the reader needs: a field equal to the default
// record's (to the bit: the same text) is left out.
template <class R>
json allFields(const R& r, const std::string& path) {
  json out = json::object();
  FieldWriter writer(out, path);
  R copy = r;  // describe() takes a record it may change; the writer only reads it
  schema::describe(writer, copy);
  return out;
}

// What a scene file needs more than the C++ API (scene_reader.cpp's fileRules): a rigid velocity
// motor's bound, a spring's stiffness or damping stated.
void fileRules(json&, const JointMotor& m, const std::string& path) {
  if (!m.isServo() && !std::isfinite(m.max_force))
    fail(childPath(path, "max_force"),
         "a velocity motor in a scene file needs a finite max_force, this one has none");
}
void fileRules(json& j, const JointSpring& s, const std::string& path) {
  if (!j.contains("stiffness") && !j.contains("damping"))
    j["stiffness"] = number(s.stiffness, childPath(path, "stiffness"));
}
template <class R>
void fileRules(json&, const R&, const std::string&) {}

template <class R>
json record(const R& r, const std::string& path) {
  if constexpr (requires { schema::rules(r); }) {
    if (const auto p = schema::rules(r))
      fail(p->field.empty() ? path : childPath(path, p->field), p->problem);
  }
  json out = allFields(r, path);
  const json defaults = allFields(R{}, path);
  for (const auto& [key, value] : defaults.items())
    if (out.contains(key) && out[key].dump() == value.dump()) out.erase(key);
  fileRules(out, r, path);
  return out;
}

// Writers for each part of the format, in the reader's order and with its field names.
class Writer {
 public:
  explicit Writer(const Scene& scene) : scene_(scene) {}

  json scene() const {
    const WorldSettings& s = scene_.settings;
    json root;
    root["gravity"] = vec3(s.gravity, "gravity");
    root["timestep"] = number(s.timestep, "timestep");
    root["duration"] = number(scene_.duration, "duration");
    putIfChanged(root, "threads", s.threads, WorldSettings{}.threads);
    putSection(root, "solver", solver(s.solver));
    // The type alone as a string, as files mostly give it.
    const json integrator = record(s.integrator, "integrator");
    if (integrator.size() == 1 && integrator.contains("type"))
      root["integrator"] = integrator["type"];
    else
      putSection(root, "integrator", integrator);
    putSection(root, "contact", contact(s.contact));
    putSection(root, "sleep", sleep(s.sleep));
    putSection(root, "faults", faults(s.faults));
    if (scene_.view) root["view"] = view(*scene_.view);

    json bodies = json::array();
    for (std::size_t i = 0; i < scene_.bodies.size(); ++i)
      bodies.push_back(body(scene_.bodies[i], itemPath("bodies", i)));
    root["bodies"] = std::move(bodies);
    if (!scene_.joints.empty()) {
      json joints = json::array();
      for (std::size_t i = 0; i < scene_.joints.size(); ++i)
        joints.push_back(joint(scene_.joints[i], itemPath("joints", i)));
      root["joints"] = std::move(joints);
    }
    if (!scene_.springs.empty()) {
      json springs = json::array();
      for (std::size_t i = 0; i < scene_.springs.size(); ++i)
        springs.push_back(spring(scene_.springs[i], itemPath("springs", i)));
      root["springs"] = std::move(springs);
    }
    loads(root);
    return root;
  }

 private:
  // --- Settings --------------------------------------------------------------------------------

  static json solver(const SolverSettings& s) { return record(s, "solver"); }
  static json contact(const ContactSettings& c) { return record(c, "contact"); }
  static json sleep(const SleepSettings& s) { return record(s, "sleep"); }
  static json faults(const FaultSettings& s) { return record(s, "faults"); }
  static json view(const SceneView& v) { return record(v, "view"); }

  // --- Bodies ----------------------------------------------------------------------------------

  json body(const BodyDef& b, const std::string& path) const {
    const BodyDef d;
    json j;
    j["name"] = b.name;
    putIfChanged(j, "static", b.is_static, d.is_static);
    putIfChanged(j, "kinematic", b.kinematic, d.kinematic);
    if (b.path) {
      if (!same<3>(b.linear_velocity, Vec3::Zero()))
        fail(childPath(path, "linear_velocity"), "a body on a path takes its velocity from it");
      j["path"] = vectorSignal(*b.path, childPath(path, "path"));
    }
    if (b.mass) j["mass"] = number(*b.mass, childPath(path, "mass"));
    if (b.inertia) j["inertia"] = inertia(*b.inertia, childPath(path, "inertia"));
    j["position"] = vec3(b.position, childPath(path, "position"));
    if (!same(b.orientation, d.orientation))
      j["orientation"] = orientation(b.orientation, childPath(path, "orientation"));
    putIfChanged(j, "linear_velocity", b.linear_velocity, d.linear_velocity, path);
    putIfChanged(j, "angular_velocity", b.angular_velocity, d.angular_velocity, path);
    putIfChanged(j, "linear_damping", b.linear_damping, d.linear_damping, path);
    putIfChanged(j, "angular_damping", b.angular_damping, d.angular_damping, path);
    if (!b.shapes.empty()) {
      json shapes = json::array();
      for (std::size_t k = 0; k < b.shapes.size(); ++k)
        shapes.push_back(shape(b.shapes[k], itemPath(childPath(path, "shapes"), k)));
      j["shapes"] = std::move(shapes);
    }
    return j;
  }

  // A mesh is written inline (points and triangles), whatever file it was read from.
  static json shape(const ShapeDef& s, const std::string& path) {
    const ShapeDef d;
    json j;
    j["type"] = shapeTypeName(s.type);
    switch (s.type) {
      case ShapeType::Sphere:
        j["radius"] = number(s.radius, childPath(path, "radius"));
        break;
      case ShapeType::Box:
        j["size"] = vec3(s.size, childPath(path, "size"));
        break;
      case ShapeType::Ellipsoid:
        j["radii"] = vec3(s.radii, childPath(path, "radii"));
        break;
      case ShapeType::Capsule:
      case ShapeType::Cylinder:
        j["radius"] = number(s.radius, childPath(path, "radius"));
        j["length"] = number(s.length, childPath(path, "length"));
        break;
      case ShapeType::Plane:
        j["normal"] = direction(s.normal, childPath(path, "normal"));
        putIfChanged(j, "offset", s.offset, d.offset, path);
        break;
      case ShapeType::Convex:
        j["points"] = points(s.points, childPath(path, "points"));
        break;
      case ShapeType::Mesh:
        j["points"] = points(s.points, childPath(path, "points"));
        j["triangles"] = triangles(s.triangles);
        break;
    }
    putIfChanged(j, "position", s.position, d.position, path);
    if (!same(s.orientation, d.orientation))
      j["orientation"] = orientation(s.orientation, childPath(path, "orientation"));
    if (s.density) j["density"] = number(*s.density, childPath(path, "density"));
    putIfChanged(j, "friction", s.friction, d.friction, path);
    putIfChanged(j, "restitution", s.restitution, d.restitution, path);
    if (s.group != d.group) j["group"] = s.group;
    if (s.mask != d.mask) j["mask"] = s.mask;
    return j;
  }

  static json points(const std::vector<Vec3>& points, const std::string& path) {
    json out = json::array();
    for (std::size_t i = 0; i < points.size(); ++i)
      out.push_back(vec3(points[i], itemPath(path, i)));
    return out;
  }

  static json triangles(const std::vector<std::array<int, 3>>& triangles) {
    json out = json::array();
    for (const auto& t : triangles) out.push_back(json::array({t[0], t[1], t[2]}));
    return out;
  }

  // --- Joints ----------------------------------------------------------------------------------

  // Body `id` by name; the world is left out of a joint (an omitted body2).
  std::string bodyName(BodyId id, const std::string& field) const {
    if (id.isWorld()) fail(field, "must be a body, not the world");
    if (id.index >= static_cast<int>(scene_.bodies.size()))
      fail(field, fmt::format("no body {} in a scene of {}", id.index, scene_.bodies.size()));
    return scene_.bodies[static_cast<std::size_t>(id.index)].name;
  }

  // Where the world puts body `id`'s centre of mass when it makes it (the world frame's origin
  // for the world): a joint's default anchor, which the reader states.
  Vec3 centreAtCreation(BodyId id) const {
    if (id.isWorld()) return Vec3::Zero();
    BodyDef def = scene_.bodies[static_cast<std::size_t>(id.index)];
    try {
      completeMassProperties(def);  // a body given without its mass moves to its shapes' centre
    } catch (const std::invalid_argument&) {
      // The world will refuse the body; its stated position is the best there is.
    }
    return def.position;
  }

  // A joint a mimic joint ties: one before it in the scene (JointId indexes Scene::joints).
  std::string jointName(const std::optional<JointId>& id, const std::string& path) const {
    if (!id || id->index < 0 || static_cast<std::size_t>(id->index) >= scene_.joints.size())
      fail(path, "not a joint of the scene");
    return scene_.joints[static_cast<std::size_t>(id->index)].def.name;
  }

  json joint(const SceneJoint& joint, const std::string& path) const {
    const JointTypeInfo* info = findJointType(joint.type);
    if (!info) fail(childPath(path, "type"), fmt::format("unknown joint type '{}'", joint.type));
    const JointDef& d = joint.def;
    json j;
    j["name"] = d.name;
    j["type"] = joint.type;
    if (!info->couplesJoints()) {  // a tie's bodies are the follower's
      j["body1"] = bodyName(d.body1, childPath(path, "body1"));
      if (!d.body2.isWorld()) j["body2"] = bodyName(d.body2, childPath(path, "body2"));
      if (d.local) j["frame"] = "local";
    }
    for (const TypeField& f : info->fields) jointField(j, f.field, d, path);
    coordinates(j, *info, d, path);
    if (d.erp) j["erp"] = number(*d.erp, childPath(path, "erp"));
    if (d.cfm) j["cfm"] = number(*d.cfm, childPath(path, "cfm"));
    if (!info->couplesJoints()) putIfChanged(j, "collide", d.collide, JointDef{}.collide);
    if (d.break_force) j["break_force"] = number(*d.break_force, childPath(path, "break_force"));
    if (d.break_torque)
      j["break_torque"] = number(*d.break_torque, childPath(path, "break_torque"));
    return j;
  }

  // One of the type's own fields (JointTypeInfo::fields), as the reader reads it back.
  void jointField(json& j, JointField field, const JointDef& d, const std::string& path) const {
    const std::string key(jointFieldName(field));
    const std::string at = childPath(path, key);
    // A default point is the body's position: the origin of its own frame.
    const auto centre = [&](BodyId id) { return d.local ? Vec3::Zero() : centreAtCreation(id); };
    switch (field) {
      case JointField::Anchor:
        j[key] = vec3(d.anchor.value_or(centre(d.body1)), at);
        break;
      case JointField::Anchor1:
        j[key] = vec3(d.anchor.value_or(centre(d.body1)), at);
        break;
      case JointField::Anchor2:
        j[key] = vec3(d.anchor2.value_or(centre(d.body2)), at);
        break;
      case JointField::Axis:
      case JointField::Axis1:
        j[key] = direction(d.axis, at);
        break;
      case JointField::Axis2:
        j[key] = direction(d.axis2, at);
        break;
      case JointField::Length:
        if (d.length) j[key] = number(*d.length, at);
        break;
      case JointField::Rope:
        if (d.rope) j[key] = true;
        break;
      case JointField::Cone:
        if (d.cone)
          j[key] = json{{"swing1", number(d.cone->swing1, childPath(at, "swing1"))},
                        {"swing2", number(d.cone->swing2, childPath(at, "swing2"))}};
        break;
      case JointField::Ratio:
        j[key] = number(d.ratio, at);
        break;
      case JointField::Axes:
        break;  // with their coordinates (coordinates())
      case JointField::Leader:
        j[key] = jointName(d.leader, at);
        break;
      case JointField::Follower:
        j[key] = jointName(d.follower, at);
        break;
      case JointField::Offset:
        putIfChanged(j, key, d.offset, 0.0, path);
        break;
    }
  }

  // A joint with one free coordinate takes its fields as its own; one with several, an object per
  // coordinate named as the type names it.
  static void coordinates(json& j, const JointTypeInfo& info, const JointDef& d,
                          const std::string& path) {
    const int free = info.freeCoordinates(d);
    if (info.usesAxes()) {  // each axis with what acts on its coordinate
      json axes = json::array();
      for (std::size_t i = 0; i < d.axes.size(); ++i) {
        const std::string item = itemPath(childPath(path, "axes"), i);
        json axis = {{"type", d.axes[i].linear ? "slider" : "hinge"},
                     {"axis", direction(d.axes[i].axis, childPath(item, "axis"))}};
        if (!d.axes[i].linear) axis["anchor"] = vec3(d.axes[i].anchor, childPath(item, "anchor"));
        if (i < d.coordinates.size()) axis.update(coordinate(d.coordinates[i], item));
        axes.push_back(std::move(axis));
      }
      j["axes"] = std::move(axes);
    }
    for (int i = 0; i < kMaxCoordinates; ++i) {
      const CoordinateDef& c = d.coordinates[static_cast<std::size_t>(i)];
      if (i >= free) {
        if (!(c.empty() && same(c.reference, 0.0) && !c.initial))
          fail(itemPath(childPath(path, "coordinates"), static_cast<std::size_t>(i)),
               fmt::format("a {} joint has {} free coordinates", info.name, free));
        continue;
      }
      if (info.usesAxes()) continue;  // written with its axis
      if (free == 1) {
        j.update(coordinate(c, path));
        continue;
      }
      const std::string name(info.coordinates[static_cast<std::size_t>(i)].name);
      json fields = coordinate(c, childPath(path, name));
      if (!fields.empty()) j[name] = std::move(fields);
    }
  }

  // What acts on a free coordinate: the fields the reader's coordinate() takes.
  static json coordinate(const CoordinateDef& c, const std::string& path) {
    return record(c, path);
  }

  // A top-level spring: a spring joint with a spring and nothing else, whose shapes collide.
  json spring(const SceneJoint& joint, const std::string& path) const {
    const JointDef& d = joint.def;
    const CoordinateDef& c = d.coordinates[0];
    const auto unset = [](const CoordinateDef& other) {
      return other.empty() && same(other.reference, 0.0) && !other.initial;
    };
    const bool spring_only = c.spring && !c.limits && !c.motor && same(c.friction, 0.0) &&
                             !c.locked && !c.prescribed && same(c.reference, 0.0) && !c.initial &&
                             std::all_of(d.coordinates.begin() + 1, d.coordinates.end(), unset);
    if (joint.type != "spring" || !spring_only || d.erp || d.cfm || d.break_force ||
        d.break_torque || !d.collide)
      fail(path,
           "a top-level spring is a spring joint with a spring and nothing else, whose bodies "
           "collide (give it in joints instead)");
    const JointSpring& s = *c.spring;
    if (!(s.rest >= 0.0)) fail(childPath(path, "rest_length"), "must be >= 0");
    json j;
    j["name"] = d.name;
    j["body1"] = bodyName(d.body1, childPath(path, "body1"));
    if (!d.body2.isWorld()) j["body2"] = bodyName(d.body2, childPath(path, "body2"));
    j["anchor1"] = vec3(d.anchor.value_or(centreAtCreation(d.body1)), childPath(path, "anchor1"));
    j["anchor2"] = vec3(d.anchor2.value_or(centreAtCreation(d.body2)), childPath(path, "anchor2"));
    putIfChanged(j, "stiffness", s.stiffness, 0.0, path);
    putIfChanged(j, "damping", s.damping, 0.0, path);
    j["rest_length"] = number(s.rest, childPath(path, "rest_length"));
    return j;
  }

  // --- Loads -----------------------------------------------------------------------------------

  // A file lists its forces (each at a point or at the centre of mass), then its torques, and the
  // world applies them in that order: each load must be one or the other, forces first.
  void loads(json& root) const {
    json forces = json::array(), torques = json::array();
    for (std::size_t i = 0; i < scene_.loads.size(); ++i) {
      const SceneLoad& load = scene_.loads[i];
      const LoadDef& l = load.def;
      const std::string path = load.field.empty() ? itemPath("loads", i) : load.field;
      // Which list it came from, else what it holds.
      const bool torque_only = load.field.starts_with("torques")  ? true
                               : load.field.starts_with("forces") ? false
                                                                  : !l.torque.isZero();
      const bool both = torque_only ? !l.force.isZero() || l.point.has_value() : !l.torque.isZero();
      if (both) fail(path, "a load with both a force and a torque (a file gives them apart)");
      if (!torque_only && !torques.empty())
        fail(path, "a force after a torque (a file's forces come before its torques)");
      json j;
      j["body"] = bodyName(l.body, childPath(path, "body"));
      if (torque_only) {
        j["torque"] = vectorSignal(l.torque, childPath(path, "torque"));
        torques.push_back(std::move(j));
      } else {
        j["force"] = vectorSignal(l.force, childPath(path, "force"));
        if (l.point) j["point"] = vec3(*l.point, childPath(path, "point"));
        forces.push_back(std::move(j));
      }
    }
    if (!forces.empty()) root["forces"] = std::move(forces);
    if (!torques.empty()) root["torques"] = std::move(torques);
  }

  const Scene& scene_;
};

}  // namespace

std::string writeSceneJson(const Scene& scene) {
  return Writer(scene).scene().dump(2) + "\n";
}

}  // namespace linx
