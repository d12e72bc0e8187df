// Reads and validates JSON scene files (docs/scene-format.md). Every problem is reported as a
// SceneError that names the file, the field's path (`bodies[2].mass`) and what is wrong, and
// nothing is built until the whole file has been checked.
#include <linx/bounds.hpp>
#include <linx/mass_properties.hpp>
#include <linx/scene.hpp>
#include <linx/shape.hpp>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <system_error>
#include <utility>

#include "collision/geometry.hpp"
#include "io/input_file.hpp"
#include "io/mesh_file.hpp"
#include "io/mimic_cycles.hpp"
#include "io/quoting.hpp"
#include "io/suggestion.hpp"
#include "io/text_number.hpp"
#include "io/unit_vectors.hpp"
#include "schema/describe.hpp"

namespace linx {

SceneError::SceneError(std::string file, std::string field, std::string problem)
    // Shown as a terminal would show it safely: a NUL in a path no longer ends the message.
    : std::runtime_error(io::visible(field.empty()
                                         ? fmt::format("{}: {}", file, problem)
                                         : fmt::format("{}: {}: {}", file, field, problem))),
      file_(std::move(file)),
      field_(std::move(field)),
      problem_(std::move(problem)) {}

namespace {

// Ordered: objects keep the file's order, so that their fields are read, and their problems found,
// in it.
using json = nlohmann::ordered_json;

std::string childPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : fmt::format("{}.{}", parent, key);
}

std::string itemPath(const std::string& parent, std::size_t index) {
  return fmt::format("{}[{}]", parent, index);
}

// Follows the parser through the document so that a duplicate key, or a number too large for a
// double, can be reported with the path of the field where it happens.
class PathTracker {
 public:
  explicit PathTracker(const std::string& file) : file_(file) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        countItem();
        // No scene nests deeper than a few levels; a hostile one nested 100,000 deep would be
        // copied recursively when the ordered objects around it grow (and overflow the stack).
        if (levels_.size() >= kMaxDepth)
          throw SceneError(
              file_, current(),
              fmt::format("nested deeper than {} levels of arrays and objects", kMaxDepth));
        levels_.push_back({event == json::parse_event_t::array_start, -1, {}, {}});
        break;
      case json::parse_event_t::key: {
        Level& level = levels_.back();
        level.key = parsed.get<std::string>();
        // An object keeps its fields in the file's order, found by a linear search: no scene's has
        // more than a few dozen, and a hostile one of a million would take hours.
        if (level.keys.size() >= kMaxKeys)
          throw SceneError(file_, current(),
                           fmt::format("more than {} fields in one object", kMaxKeys));
        if (!level.keys.insert(level.key).second) {
          throw SceneError(file_, current(), "duplicate key");
        }
        break;
      }
      case json::parse_event_t::value:
        countItem();
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        levels_.pop_back();
        break;
    }
    return true;
  }

  /// Path of the value the parser is reading.
  std::string current() const {
    std::string path;
    for (std::size_t i = 0; i < levels_.size(); ++i) {
      const Level& level = levels_[i];
      const bool innermost = i + 1 == levels_.size();
      if (level.is_array) {
        // The innermost array's next item has not been counted yet.
        path = itemPath(path, static_cast<std::size_t>(level.index + (innermost ? 1 : 0)));
      } else {
        path = childPath(path, level.key);
      }
    }
    return path;
  }

 private:
  struct Level {
    bool is_array = false;
    long index = -1;  // arrays: the item being read
    std::string key;  // objects: the key being read
    std::set<std::string> keys;
  };

  void countItem() {
    if (!levels_.empty() && levels_.back().is_array) ++levels_.back().index;
  }

  static constexpr std::size_t kMaxDepth = 256;
  static constexpr std::size_t kMaxKeys = 4096;
  const std::string& file_;
  std::vector<Level> levels_;
};

// "a string", "an array", ... for messages about a value of the wrong type.
std::string describe(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "a number";
    default:
      return "an unsupported value";
  }
}

// Text from a file as a message quotes it: bytes that are not printable ASCII escaped (\xNN), at
// most `limit` characters.
std::string shownText(std::string_view text, std::size_t limit = 60) {
  std::string out;
  for (const char c : text.substr(0, limit)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f)
      out += c;
    else
      out += fmt::format("\\x{:02x}", byte);
  }
  return text.size() > limit ? out + "..." : out;
}

// " (did you mean 'mass'?)" when one of `names` is close to `name`, else "".
template <typename Names>
std::string suggestion(std::string_view name, const Names& names) {
  const std::string_view best = io::closestName(name, names);
  return best.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", best);
}

// The names of a described record's fields, and their aliases (other formats' names for them).
class FieldNames {
 public:
  template <class T>
  void field(T&, const schema::FieldInfo& info) {
    fields_.push_back(info);
  }
  // " (did you mean 'max_force'?)" for a name close to a field's, or one of its aliases.
  std::string suggestion(std::string_view name) const {
    for (const schema::FieldInfo& f : fields_)
      for (std::string_view alias : f.aliases)
        if (alias == name) return fmt::format(" (did you mean '{}'?)", f.name);
    std::vector<std::string_view> names;
    for (const schema::FieldInfo& f : fields_) names.push_back(f.name);
    if (const std::string_view best = io::closestName(name, names); !best.empty())
      return fmt::format(" (did you mean '{}'?)", best);
    for (const schema::FieldInfo& f : fields_)
      for (std::string_view alias : f.aliases)
        if (io::editDistance(name, alias) <= 1) return fmt::format(" (did you mean '{}'?)", f.name);
    // A word of a longer name: "velocity" for "target_velocity".
    for (const schema::FieldInfo& f : fields_) {
      const auto at = f.name.find(name);
      const bool word = at != std::string_view::npos && name.size() >= 3 &&
                        (at == 0 || f.name[at - 1] == '_') &&
                        (at + name.size() == f.name.size() || f.name[at + name.size()] == '_');
      if (word) return fmt::format(" (did you mean '{}'?)", f.name);
    }
    return {};
  }
  bool has(std::string_view name) const {
    return std::any_of(fields_.begin(), fields_.end(),
                       [&](const schema::FieldInfo& f) { return f.name == name; });
  }
  std::vector<std::string_view> names() const {
    std::vector<std::string_view> out;
    for (const schema::FieldInfo& f : fields_) out.push_back(f.name);
    return out;
  }

 private:
  std::vector<schema::FieldInfo> fields_;
};

template <class R>
FieldNames fieldNames() {
  FieldNames names;
  R r{};
  schema::describe(names, r);
  return names;
}

// What acts on a joint's free coordinate (CoordinateDef): its fields' names.
const std::vector<std::string_view> kCoordinateFields = fieldNames<CoordinateDef>().names();

// A value in the document and its path, for messages.
struct Node {
  const json& value;
  std::string path;
};

// Validating readers for each part of the format. Each one fails with the path of the field.
class Reader {
 public:
  Reader(const std::string& file, const ImportOptions& options) : file_(file), options_(options) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw SceneError(file_, path, problem);
  }

  Scene scene(const json& root) const {
    const Node node{root, ""};
    if (!root.is_object())
      fail("", fmt::format("a scene must be a JSON object, got {}", describe(root)));
    allowOnly(node,
              {"gravity", "timestep", "duration", "threads", "solver", "integrator", "contact",
               "sleep", "faults", "bodies", "joints", "springs", "forces", "torques", "view"});

    Scene scene;
    scene.file = file_;
    if (auto n = get(node, "gravity")) scene.settings.gravity = vec3(*n);
    if (auto n = get(node, "timestep")) scene.settings.timestep = timestep(*n);
    if (auto n = get(node, "duration")) scene.duration = positive(*n);
    if (auto n = get(node, "threads")) {
      scene.settings.threads = integer(*n, 0);
      if (scene.settings.threads > kMaxThreads)
        fail(n->path,
             fmt::format("must be at most {}, got {}", kMaxThreads, scene.settings.threads));
    }
    if (auto n = get(node, "solver")) scene.settings.solver = solver(*n);
    if (auto n = get(node, "integrator")) scene.settings.integrator = integrator(*n);
    if (auto n = get(node, "contact")) scene.settings.contact = contact(*n);
    if (auto n = get(node, "sleep")) scene.settings.sleep = sleep(*n);
    if (auto n = get(node, "faults")) scene.settings.faults = faults(*n);
    if (auto n = get(node, "view")) scene.view = view(*n);

    const Node bodies = require(node, "bodies");
    expectArray(bodies);
    if (bodies.value.empty()) fail(bodies.path, "must contain at least one body");
    std::map<std::string, std::size_t> body_index;
    // Where each body's centre of mass is in the frame the file states it in (not zero for a body
    // that takes its mass from its shapes): joints in local frames are given in the stated frame.
    std::vector<Vec3> centres;
    for (std::size_t i = 0; i < bodies.value.size(); ++i) {
      const Node item{bodies.value[i], itemPath(bodies.path, i)};
      BodyDef def = body(item);
      const auto stated = get(item, "position");
      centres.push_back(def.orientation.normalized().conjugate() *
                        (def.position - (stated ? vec3(*stated) : Vec3::Zero())));
      const auto [it, inserted] = body_index.emplace(def.name, i);
      if (!inserted) {
        fail(childPath(item.path, "name"),
             fmt::format("duplicate body name '{}' (also bodies[{}])", def.name, it->second));
      }
      scene.bodies.push_back(std::move(def));
    }

    if (auto joints = get(node, "joints")) {
      expectArray(*joints);
      std::map<std::string, std::size_t> joint_index;
      for (std::size_t i = 0; i < joints->value.size(); ++i) {
        const Node item{joints->value[i], itemPath(joints->path, i)};
        SceneJoint joint = this->joint(item, scene.bodies, body_index, centres, scene.joints);
        const auto [it, inserted] = joint_index.emplace(joint.def.name, i);
        if (!inserted) {
          fail(childPath(item.path, "name"),
               fmt::format("duplicate joint name '{}' (also joints[{}])", joint.def.name,
                           it->second));
        }
        scene.joints.push_back(std::move(joint));
      }
      if (const auto cycle = io::findMimicCycle(scene))
        fail(childPath(itemPath(joints->path, cycle->mimic), "leader"), cycle->problem);
    }
    if (auto springs = get(node, "springs")) {
      expectArray(*springs);
      std::set<std::string> joint_names;
      for (const SceneJoint& j : scene.joints) joint_names.insert(j.def.name);
      for (std::size_t i = 0; i < springs->value.size(); ++i) {
        const Node item{springs->value[i], itemPath(springs->path, i)};
        SceneJoint joint = spring(item, scene.bodies, body_index);
        if (!joint_names.insert(joint.def.name).second)
          fail(
              childPath(item.path, "name"),
              fmt::format("duplicate name '{}' (springs share names with joints)", joint.def.name));
        scene.springs.push_back(std::move(joint));
      }
    }
    for (const bool forces : {true, false}) {
      const auto list = get(node, forces ? "forces" : "torques");
      if (!list) continue;
      expectArray(*list);
      for (std::size_t i = 0; i < list->value.size(); ++i) {
        const Node item{list->value[i], itemPath(list->path, i)};
        scene.loads.push_back(SceneLoad{item.path, load(item, forces, scene.bodies, body_index)});
      }
    }
    return scene;
  }

 private:
  // --- Structure -------------------------------------------------------------------------------

  void expectObject(const Node& n) const {
    if (!n.value.is_object())
      fail(n.path, fmt::format("expected an object, got {}", describe(n.value)));
  }

  void expectArray(const Node& n) const {
    if (!n.value.is_array())
      fail(n.path, fmt::format("expected an array, got {}", describe(n.value)));
  }

  // Fails on the first key of the object `n` that is not in `allowed`.
  void allowOnly(const Node& n, std::initializer_list<std::string_view> allowed) const {
    allowOnly(n, std::vector<std::string_view>(allowed));
  }
  void allowOnly(const Node& n, std::span<const std::string_view> allowed) const {
    expectObject(n);
    for (const auto& [key, value] : n.value.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        fail(childPath(n.path, key), "unknown field" + suggestion(key, allowed));
      }
    }
  }

  std::optional<Node> get(const Node& object, std::string_view key) const {
    const auto it = object.value.find(key);
    if (it == object.value.end()) return std::nullopt;
    return Node{*it, childPath(object.path, key)};
  }

  Node require(const Node& object, std::string_view key) const {
    auto n = get(object, key);
    if (!n) fail(childPath(object.path, key), "missing required field");
    return *n;
  }

  // --- Values ----------------------------------------------------------------------------------

  double number(const Node& n) const {
    if (!n.value.is_number())
      fail(n.path, fmt::format("expected a number, got {}", describe(n.value)));
    const double x = n.value.get<double>();
    if (!std::isfinite(x)) fail(n.path, "number out of range");
    return x;
  }

  double positive(const Node& n) const {
    const double x = number(n);
    if (!(x > 0)) fail(n.path, fmt::format("must be > 0, got {}", x));
    return x;
  }

  // At least kMinTimestep: the step forms h^2, which must stay a normal double.
  double timestep(const Node& n) const {
    const double h = positive(n);
    if (h < kMinTimestep)
      fail(n.path, fmt::format("{:g} s is below {:g} s, the shortest step whose square (the step "
                               "forms h^2) is a normal double",
                               h, kMinTimestep));
    return h;
  }

  double nonNegative(const Node& n) const {
    const double x = number(n);
    if (x < 0) fail(n.path, fmt::format("must be >= 0, got {}", x));
    return x;
  }

  double unitInterval(const Node& n) const {
    const double x = number(n);
    if (x < 0 || x > 1) fail(n.path, fmt::format("must be between 0 and 1, got {}", x));
    return x;
  }

  int integer(const Node& n, int min) const {
    const double x = number(n);
    if (x > std::numeric_limits<int>::max())
      fail(n.path, fmt::format("must be an integer from {} to {}, got {:g}", min,
                               std::numeric_limits<int>::max(), x));
    if (x != std::floor(x) || x < min)
      fail(n.path, fmt::format("must be an integer >= {}, got {}", min, n.value.dump()));
    return static_cast<int>(x);
  }

  bool boolean(const Node& n) const {
    if (!n.value.is_boolean()) {
      fail(n.path, fmt::format("expected true or false, got {}", describe(n.value)));
    }
    return n.value.get<bool>();
  }

  std::string string(const Node& n) const {
    if (!n.value.is_string())
      fail(n.path, fmt::format("expected a string, got {}", describe(n.value)));
    return n.value.get<std::string>();
  }

  template <int N>
  Eigen::Matrix<double, N, 1> vector(const Node& n) const {
    if (!n.value.is_array() || n.value.size() != N) {
      fail(n.path, fmt::format("expected an array of {} numbers, got {}", N,
                               n.value.is_array() ? fmt::format("{} items", n.value.size())
                                                  : describe(n.value)));
    }
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = number({n.value[i], itemPath(n.path, i)});
    return v;
  }

  Vec3 vec3(const Node& n) const { return vector<3>(n); }

  // A direction: any non-zero vector, returned of unit length (io::readNormalized).
  Vec3 direction(const Node& n) const {
    const Vec3 v = vec3(n);
    if (!(v.stableNorm() > 0)) fail(n.path, "must not be zero");
    return io::readNormalized<3>(v);
  }

  // --- Described records (src/schema/describe.hpp) ----------------------------------------------

  // Reads one field of a described record, the one the file's key names.
  class FieldReader {
   public:
    FieldReader(const Reader& reader, std::string_view key, const Node& node)
        : reader_(reader), key_(key), node_(node) {}
    bool found() const { return found_; }

    void field(double& x, const schema::FieldInfo& info) {
      if (mine(info)) x = inRange(reader_.number(node_), info);
    }
    void field(int& x, const schema::FieldInfo& info) {
      if (!mine(info)) return;
      const double v = reader_.number(node_);
      if (v > std::numeric_limits<int>::max())
        reader_.fail(node_.path, fmt::format("must be an integer from {} to {}, got {:g}",
                                             info.range.lower, std::numeric_limits<int>::max(), v));
      if (v != std::floor(v)) reader_.fail(node_.path, info.range.problem(v, true));
      x = static_cast<int>(inRange(v, info, true));
    }
    void field(bool& x, const schema::FieldInfo& info) {
      if (mine(info)) x = reader_.boolean(node_);
    }
    void field(Signal& x, const schema::FieldInfo& info) {
      if (mine(info)) x = reader_.signal(node_);
    }
    void field(std::optional<double>& x, const schema::FieldInfo& info) {
      if (mine(info)) x = inRange(reader_.number(node_), info);
    }
    void field(std::optional<Vec3>& x, const schema::FieldInfo& info) {
      if (mine(info)) x = info.direction ? reader_.direction(node_) : reader_.vec3(node_);
    }
    void field(std::optional<Signal>& x, const schema::FieldInfo& info) {
      if (mine(info)) x = reader_.signal(node_);
    }
    template <class R>
    requires schema::kIsRecord<R>
    void field(std::optional<R>& x, const schema::FieldInfo& info) {
      if (mine(info)) x = reader_.record<R>(node_);
    }
    template <class E>
    requires std::is_enum_v<E>
    void field(E& x, const schema::FieldInfo& info) {
      if (!mine(info)) return;
      const std::string name = reader_.string(node_);
      const auto it = std::find(info.choices.begin(), info.choices.end(), name);
      if (it == info.choices.end()) {
        std::string expected;
        for (std::size_t i = 0; i < info.choices.size(); ++i)
          expected += fmt::format("{}\"{}\"",
                                  i == 0                         ? ""
                                  : i + 1 == info.choices.size() ? " or "
                                                                 : ", ",
                                  info.choices[i]);
        reader_.fail(node_.path, fmt::format("unknown value '{}' (expected {})", name, expected));
      }
      x = static_cast<E>(it - info.choices.begin());
    }

   private:
    bool mine(const schema::FieldInfo& info) {
      if (info.name != key_) return false;
      found_ = true;
      return true;
    }
    double inRange(double x, const schema::FieldInfo& info, bool integer = false) const {
      if (!info.range.contains(x)) reader_.fail(node_.path, info.range.problem(x, integer));
      return x;
    }

    const Reader& reader_;
    std::string_view key_;
    const Node& node_;
    bool found_ = false;
  };

  // The fields of `n` that record R describes, into `r`, in the file's order. Another field is
  // an error where it comes when `only_these`; else it is left to the caller (a joint's own).
  template <class R>
  void readFields(const Node& n, R& r, bool only_these) const {
    for (const auto& [key, value] : n.value.items()) {
      const Node field{value, childPath(n.path, key)};
      FieldReader reader(*this, key, field);
      schema::describe(reader, r);
      if (!reader.found() && only_these)
        fail(field.path, "unknown field" + fieldNames<R>().suggestion(key));
    }
  }

  // The record's rules, a problem named by its field (or the record).
  template <class R>
  void applyRules(const Node& n, const R& r) const {
    if constexpr (requires { schema::rules(r); }) {
      if (const auto p = schema::rules(r))
        fail(p->field.empty() ? n.path : childPath(n.path, p->field), p->problem);
    }
  }

  // A described record: an object of its fields alone, each checked as it comes in the file, an
  // unknown one named with the closest field's name; then its rules.
  template <class R>
  R record(const Node& n, R r = {}) const {
    expectObject(n);
    readFields(n, r, true);
    applyRules(n, r);
    fileRules(n, r);
    return r;
  }

  SceneView view(const Node& n) const { return record<SceneView>(n); }

  // [w, x, y, z], normalized.
  Quat orientation(const Node& n) const {
    const Eigen::Vector4d c = vector<4>(n);
    if (!(c.stableNorm() > 0))
      fail(n.path, "must not be zero (a rotation quaternion [w, x, y, z])");
    const Eigen::Vector4d u = io::readNormalized<4>(c);
    return Quat(u[0], u[1], u[2], u[3]);
  }

  // Principal moments [Ixx, Iyy, Izz] or a full symmetric positive definite 3x3 matrix.
  Mat3 inertia(const Node& n) const {
    if (n.value.is_array() && n.value.size() == 3 && n.value[0].is_array()) {
      Mat3 m;
      for (int r = 0; r < 3; ++r) m.row(r) = vec3({n.value[r], itemPath(n.path, r)}).transpose();
      const double scale = m.cwiseAbs().maxCoeff();
      if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
        fail(n.path, "the inertia matrix must be symmetric");
      }
      m = 0.5 * (m + m.transpose());
      const Eigen::SelfAdjointEigenSolver<Mat3> eigen(m, Eigen::EigenvaluesOnly);
      if (!(eigen.eigenvalues().minCoeff() > 0)) {
        fail(n.path, "the inertia matrix must be positive definite");
      }
      return m;
    }
    if (n.value.is_array() && n.value.size() == 3) {
      Vec3 moments;
      for (int i = 0; i < 3; ++i) moments[i] = positive({n.value[i], itemPath(n.path, i)});
      return moments.asDiagonal();
    }
    fail(n.path, fmt::format("expected [Ixx, Iyy, Izz] or a 3x3 array, got {}",
                             n.value.is_array() ? fmt::format("{} items", n.value.size())
                                                : describe(n.value)));
  }

  // --- Sections --------------------------------------------------------------------------------

  // "integrator": "auto" | "step" | "accurate", or {"type": ..., "tolerance": ...}.
  IntegratorSettings integrator(const Node& n) const {
    if (n.value.is_string()) {  // the type alone
      IntegratorSettings s;
      FieldReader type(*this, "type", n);
      schema::describe(type, s);
      return s;
    }
    if (!n.value.is_object())
      fail(n.path, fmt::format("expected \"auto\", \"step\", \"accurate\" or an object, got {}",
                               describe(n.value)));
    return record<IntegratorSettings>(n);
  }

  SolverSettings solver(const Node& n) const { return record<SolverSettings>(n); }
  ContactSettings contact(const Node& n) const { return record<ContactSettings>(n); }
  SleepSettings sleep(const Node& n) const { return record<SleepSettings>(n); }
  FaultSettings faults(const Node& n) const { return record<FaultSettings>(n); }

  ShapeDef shape(const Node& n) const {
    expectObject(n);
    ShapeDef s;
    const Node type = require(n, "type");
    const std::string name = string(type);
    static constexpr std::array kTypes{ShapeType::Sphere,   ShapeType::Box,      ShapeType::Capsule,
                                       ShapeType::Cylinder, ShapeType::Plane,    ShapeType::Convex,
                                       ShapeType::Mesh,     ShapeType::Ellipsoid};
    const auto known = std::find_if(kTypes.begin(), kTypes.end(),
                                    [&](ShapeType t) { return name == shapeTypeName(t); });
    if (known == kTypes.end())
      fail(type.path, fmt::format("unknown shape type '{}' (expected sphere, box, capsule, "
                                  "cylinder, ellipsoid, plane, convex or mesh)",
                                  name));
    s.type = *known;
    // A field of another type of shape (a size on a sphere) is named as such.
    static constexpr std::array<std::pair<std::string_view, std::array<ShapeType, 2>>, 9> kOwners{{
        {"radius", {ShapeType::Sphere, ShapeType::Capsule}},
        {"size", {ShapeType::Box, ShapeType::Box}},
        {"radii", {ShapeType::Ellipsoid, ShapeType::Ellipsoid}},
        {"length", {ShapeType::Capsule, ShapeType::Cylinder}},
        {"normal", {ShapeType::Plane, ShapeType::Plane}},
        {"offset", {ShapeType::Plane, ShapeType::Plane}},
        {"points", {ShapeType::Convex, ShapeType::Mesh}},
        {"triangles", {ShapeType::Mesh, ShapeType::Mesh}},
        {"file", {ShapeType::Mesh, ShapeType::Mesh}},
    }};
    for (const auto& [key, owners] : kOwners) {
      const bool used = owners[0] == s.type || owners[1] == s.type ||
                        (key == "radius" && s.type == ShapeType::Cylinder);
      if (!used && n.value.contains(key))
        fail(childPath(n.path, key), fmt::format("not used by a {} shape", name));
    }
    // The fields each type takes, then the common ones.
    switch (s.type) {
      case ShapeType::Sphere:
        allowOnly(n, withCommon({"radius"}));
        s.radius = positive(require(n, "radius"));
        break;
      case ShapeType::Box: {
        allowOnly(n, withCommon({"size"}));
        const Node size = require(n, "size");
        s.size = vec3(size);
        for (int i = 0; i < 3; ++i) positive({size.value[i], itemPath(size.path, i)});
        break;
      }
      case ShapeType::Ellipsoid: {
        allowOnly(n, withCommon({"radii"}));
        const Node radii = require(n, "radii");
        s.radii = vec3(radii);
        for (int i = 0; i < 3; ++i) positive({radii.value[i], itemPath(radii.path, i)});
        break;
      }
      case ShapeType::Capsule:
      case ShapeType::Cylinder: {
        allowOnly(n, withCommon({"radius", "length"}));
        s.radius = positive(require(n, "radius"));
        const Node length = require(n, "length");
        // A capsule of length 0 is a sphere; a cylinder needs a length.
        s.length = s.type == ShapeType::Capsule ? nonNegative(length) : positive(length);
        break;
      }
      case ShapeType::Plane:
        allowOnly(n, withCommon({"normal", "offset"}));
        if (auto v = get(n, "normal")) s.normal = direction(*v);
        if (auto v = get(n, "offset")) s.offset = number(*v);
        break;
      case ShapeType::Convex: {
        allowOnly(n, withCommon({"points"}));
        s.points = points(require(n, "points"), 4);
        break;
      }
      case ShapeType::Mesh:
        allowOnly(n, withCommon({"file", "points", "triangles"}));
        mesh(n, s);
        break;
    }
    if (auto v = get(n, "position")) s.position = vec3(*v);
    if (auto v = get(n, "orientation")) s.orientation = orientation(*v);
    if (auto v = get(n, "density")) s.density = nonNegative(*v);
    if (auto v = get(n, "friction")) s.friction = nonNegative(*v);
    if (auto v = get(n, "restitution")) s.restitution = unitInterval(*v);
    if (auto v = get(n, "group")) s.group = static_cast<std::uint32_t>(bits(*v));
    if (auto v = get(n, "mask")) s.mask = static_cast<std::uint32_t>(bits(*v));
    if (!isSolid(s.type) && s.density)
      fail(childPath(n.path, "density"), fmt::format("a {} has no volume", name));
    if (s.type == ShapeType::Convex || s.type == ShapeType::Mesh) {
      // A hull must span a volume, a mesh must have proper triangles: check them now, so that the
      // error names the field (the world would reject them later without a path).
      try {
        collision::prepareGeometry(s);
      } catch (const std::invalid_argument& e) {
        fail(childPath(n.path, s.file.empty() ? "points" : "file"), e.what());
      }
    }
    return s;
  }

  static std::vector<std::string_view> withCommon(std::initializer_list<std::string_view> own) {
    std::vector<std::string_view> all{"type",     "position",    "orientation", "density",
                                      "friction", "restitution", "group",       "mask"};
    all.insert(all.end(), own.begin(), own.end());
    return all;
  }

  // A 32-bit collision group or mask: an integer in [0, 2^32).
  double bits(const Node& n) const {
    const double x = number(n);
    if (x != std::floor(x) || x < 0 || x > 4294967295.0)
      fail(n.path, fmt::format("must be an integer in [0, 4294967295], got {}", n.value.dump()));
    return x;
  }

  std::vector<Vec3> points(const Node& n, std::size_t at_least) const {
    expectArray(n);
    if (n.value.size() < at_least)
      fail(n.path, fmt::format("needs at least {} points, got {}", at_least, n.value.size()));
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < n.value.size(); ++i)
      out.push_back(vec3({n.value[i], itemPath(n.path, i)}));
    return out;
  }

  // A mesh from a file (OBJ or STL, relative to the scene file) or given inline.
  void mesh(const Node& n, ShapeDef& s) const {
    const auto file = get(n, "file");
    if (file) {
      for (std::string_view key : {"points", "triangles"})
        if (n.value.contains(key))
          fail(childPath(n.path, key), "give either a file or points and triangles");
      // (An empty name would reach std::filesystem, whose error text is its own.)
      if (string(*file).empty()) fail(file->path, "must not be empty");
      const std::filesystem::path path = std::filesystem::path(file_).parent_path() / string(*file);
      ShapeDef loaded;
      try {
        io::checkInsideFolder(path, std::filesystem::path(file_).parent_path(),
                              options_.allow_outside_paths);
        loaded = io::loadMeshFile(path.string());
      } catch (const std::exception& e) {
        fail(file->path, e.what());
      }
      s.points = std::move(loaded.points);
      s.triangles = std::move(loaded.triangles);
      s.file = string(*file);
      return;
    }
    s.points = points(require(n, "points"), 3);
    const Node triangles = require(n, "triangles");
    expectArray(triangles);
    if (triangles.value.empty()) fail(triangles.path, "needs at least one triangle");
    for (std::size_t t = 0; t < triangles.value.size(); ++t) {
      const Node tri{triangles.value[t], itemPath(triangles.path, t)};
      const Vec3 idx = vec3(tri);
      std::array<int, 3> v{};
      for (int k = 0; k < 3; ++k) {
        if (idx[k] != std::floor(idx[k]) || idx[k] < 0 ||
            idx[k] >= static_cast<double>(s.points.size()))
          fail(itemPath(tri.path, static_cast<std::size_t>(k)),
               fmt::format("must be a point index in [0, {}), got {}", s.points.size(),
                           tri.value[static_cast<std::size_t>(k)].dump()));
        v[static_cast<std::size_t>(k)] = static_cast<int>(idx[k]);
      }
      // Here rather than in the geometry's check, which can name only the points.
      for (std::size_t k = 0; k < 3; ++k)
        if (v[k] == v[(k + 1) % 3]) fail(tri.path, fmt::format("repeats point {}", v[k]));
      s.triangles.push_back(v);
    }
  }

  BodyDef body(const Node& n) const {
    allowOnly(n, {"name", "mass", "inertia", "position", "orientation", "linear_velocity",
                  "angular_velocity", "static", "kinematic", "path", "shapes", "linear_damping",
                  "angular_damping"});
    BodyDef b;
    const Node name = require(n, "name");
    b.name = string(name);
    if (b.name.empty()) fail(name.path, "must not be empty");
    if (b.name == "world") fail(name.path, "'world' is reserved for the fixed world frame");

    if (auto v = get(n, "static")) b.is_static = boolean(*v);
    if (auto v = get(n, "path")) {
      if (!(n.value.contains("kinematic") && n.value["kinematic"] == true))
        fail(v->path, "only a kinematic body follows a path (\"kinematic\": true)");
      if (n.value.contains("linear_velocity"))
        fail(childPath(n.path, "linear_velocity"), "a body on a path takes its velocity from it");
      b.path = vectorSignal(*v);
    }
    if (auto v = get(n, "kinematic")) {
      b.kinematic = boolean(*v);
      if (b.kinematic && b.is_static) fail(v->path, "a body is static or kinematic, not both");
      for (std::string_view key : {"mass", "inertia", "linear_damping", "angular_damping"})
        if (b.kinematic && n.value.contains(key))
          fail(childPath(n.path, key),
               "a kinematic body has infinite mass and moves at its given velocity");
    }
    if (auto v = get(n, "position")) b.position = vec3(*v);
    for (std::string_view key : {"linear_damping", "angular_damping"}) {
      auto v = get(n, key);
      if (!v) continue;
      if (b.is_static) fail(v->path, "a static body does not move");
      (key == "linear_damping" ? b.linear_damping : b.angular_damping) = nonNegative(*v);
    }
    if (auto v = get(n, "orientation")) b.orientation = orientation(*v);
    for (std::string_view key : {"linear_velocity", "angular_velocity"}) {
      auto v = get(n, key);
      if (!v) continue;
      const Vec3 velocity = vec3(*v);
      if (b.is_static && !velocity.isZero(0)) fail(v->path, "a static body cannot move");
      (key == "linear_velocity" ? b.linear_velocity : b.angular_velocity) = velocity;
    }
    if (auto shapes = get(n, "shapes")) {
      expectArray(*shapes);
      for (std::size_t i = 0; i < shapes->value.size(); ++i) {
        b.shapes.push_back(shape({shapes->value[i], itemPath(shapes->path, i)}));
      }
    }

    // Static bodies never move: their mass and inertia are checked when given, never needed.
    for (std::size_t k = 0; k < b.shapes.size(); ++k) {
      if (isStaticOnly(b.shapes[k].type) && !b.is_static)
        fail(childPath(itemPath(childPath(n.path, "shapes"), k), "type"),
             fmt::format("a {} belongs on a static body (\"static\": true)",
                         shapeTypeName(b.shapes[k].type)));
    }
    const auto mass = get(n, "mass");
    const auto given_inertia = get(n, "inertia");
    if (mass) b.mass = positive(*mass);
    if (given_inertia) b.inertia = inertia(*given_inertia);
    if (b.is_static) return b;
    if (b.kinematic) {
      for (std::size_t k = 0; k < b.shapes.size(); ++k)
        if (b.shapes[k].density)
          fail(childPath(itemPath(childPath(n.path, "shapes"), k), "density"),
               "a kinematic body has no mass (infinite)");
      return b;
    }
    // What completeMassProperties would refuse, named by its place in the file.
    const bool solid = std::any_of(b.shapes.begin(), b.shapes.end(),
                                   [](const ShapeDef& s) { return isSolid(s.type); });
    const auto density = [&](std::size_t k) {
      return childPath(itemPath(childPath(n.path, "shapes"), k), "density");
    };
    if (mass) {
      if (!given_inertia && !solid)
        fail(childPath(n.path, "inertia"),
             "missing required field (give the inertia, or a shape to compute it from)");
    } else {
      // The mass, centre of mass and inertia of the shapes at their densities.
      if (!solid) fail(childPath(n.path, "mass"), "missing required field");
      for (std::size_t k = 0; k < b.shapes.size(); ++k) {
        if (isSolid(b.shapes[k].type) && !b.shapes[k].density)
          fail(density(k),
               "missing required field (the body gives no mass: every shape needs a density)");
      }
      if (given_inertia)
        fail(childPath(n.path, "inertia"), "give the mass with the inertia, or neither");
    }
    // No mass: the shapes at their densities; a mass without inertia: its solids filled
    // uniformly, about the body origin (docs/scene-format.md). The API's message starts with the
    // field.
    try {
      completeMassProperties(b);
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      const auto colon = message.find(": ");
      fail(childPath(n.path, message.substr(0, colon)), message.substr(colon + 2));
    }
    return b;
  }

  SceneJoint joint(const Node& n, const std::vector<BodyDef>& bodies,
                   const std::map<std::string, std::size_t>& body_index,
                   std::span<const Vec3> centres, std::span<const SceneJoint> earlier) const {
    expectObject(n);
    SceneJoint joint;
    JointDef& d = joint.def;
    const Node name = require(n, "name");
    d.name = string(name);
    if (d.name.empty()) fail(name.path, "must not be empty");

    const Node type = require(n, "type");
    joint.type = string(type);
    // What each type takes comes from the joint registry (JointTypeInfo::fields).
    const JointTypeInfo* t = findJointType(joint.type);
    if (!t) {
      std::string names;
      const auto types = jointTypes();
      for (std::size_t i = 0; i < types.size(); ++i)
        names += fmt::format("{}{}",
                             i == 0                  ? ""
                             : i + 1 == types.size() ? " or "
                                                     : ", ",
                             types[i].name);
      fail(type.path, fmt::format("unknown joint type '{}' (expected {})", joint.type, names));
    }
    jointKeys(n, *t);

    if (t->couplesJoints()) {
      coupledJoints(n, joint.type, earlier, d);
      if (auto v = get(n, "ratio")) d.ratio = nonZero(*v);  // 1 by default, as URDF's multiplier
      if (auto v = get(n, "erp")) d.erp = unitInterval(*v);
      if (auto v = get(n, "cfm")) d.cfm = nonNegative(*v);
      if (auto v = get(n, "break_force")) d.break_force = positive(*v);
      if (auto v = get(n, "break_torque")) d.break_torque = positive(*v);
      return joint;
    }
    const Node body1 = require(n, "body1");
    d.body1 = bodyRef(body1, body_index, true);
    if (d.body1.isWorld()) {
      fail(body1.path, "must be a body, not the world (the world goes in body2, or leave it out)");
    }
    if (auto v = get(n, "body2")) {
      d.body2 = bodyRef(*v, body_index, true);
      if (d.body2 == d.body1) fail(v->path, "a joint needs two different bodies");
    }
    if (auto v = get(n, "frame")) {
      const std::string frame = string(*v);
      if (frame != "world" && frame != "local")
        fail(v->path, fmt::format("unknown frame '{}' (expected \"world\": the world frame at the "
                                  "start, or \"local\": each body's own frame)",
                                  frame));
      d.local = frame == "local";
    }
    // The type's own fields, as it lists them.
    if (t->usesAnchor2()) twoPoints(n, bodies, d);
    for (const TypeField& f : t->fields) jointField(n, f, *t, bodies, d);
    coordinates(n, *t, d);
    if (auto v = get(n, "erp")) d.erp = unitInterval(*v);
    if (auto v = get(n, "cfm")) d.cfm = nonNegative(*v);
    if (auto v = get(n, "collide")) d.collide = boolean(*v);
    if (auto v = get(n, "break_force")) d.break_force = positive(*v);
    if (auto v = get(n, "break_torque")) d.break_torque = positive(*v);
    if (d.local) inCentreFrames(d, centres);
    return joint;
  }

  // A joint's keys in the file's order: each one of the common fields, one of its type's, or what
  // acts on its coordinates; another type's field is named as such, anything else is unknown.
  void jointKeys(const Node& n, const JointTypeInfo& t) const {
    const int free = t.usesAxes() ? 0 : t.freeCoordinates();
    const bool limits_only = free == 1 && t.coordinates[0].limits_only;  // a ball joint's angle
    std::vector<std::string_view> allowed{"name", "type",        "erp",
                                          "cfm",  "break_force", "break_torque"};
    if (!t.couplesJoints()) allowed.insert(allowed.end(), {"body1", "body2", "frame", "collide"});
    for (const TypeField& f : t.fields) allowed.push_back(jointFieldName(f.field));
    if (limits_only)
      allowed.push_back("limits");
    else if (free == 1)
      allowed.insert(allowed.end(), kCoordinateFields.begin(), kCoordinateFields.end());
    for (int i = 0; free > 1 && i < free; ++i)
      allowed.push_back(t.coordinates[static_cast<std::size_t>(i)].name);
    const auto isJointField = [](std::string_view key) {
      for (int f = 0; f <= static_cast<int>(JointField::Offset); ++f)
        if (jointFieldName(static_cast<JointField>(f)) == key) return true;
      return key == "body1" || key == "body2" || key == "frame" || key == "collide";
    };
    for (const auto& [key, value] : n.value.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      const std::string path = childPath(n.path, key);
      const bool acts_on_coordinate = std::find(kCoordinateFields.begin(), kCoordinateFields.end(),
                                                key) != kCoordinateFields.end();
      if (acts_on_coordinate && free > 1)
        fail(path, fmt::format("a {} joint has {} coordinates: give it in one of them ({}.{})",
                               t.name, free, t.coordinates[0].name, key));
      if (acts_on_coordinate || isJointField(key))
        fail(path, fmt::format("not used by a {} joint", t.name));
      fail(path, "unknown field" + suggestion(key, allowed));
    }
  }

  // One of a type's own fields (JointTypeInfo::fields) into the definition; the two points of a
  // joint between points are read together (twoPoints), a tie's joints by coupledJoints.
  void jointField(const Node& n, const TypeField& f, const JointTypeInfo& t,
                  const std::vector<BodyDef>& bodies, JointDef& d) const {
    const std::string_view key = jointFieldName(f.field);
    const auto v = f.required ? std::optional<Node>(require(n, key)) : get(n, key);
    switch (f.field) {
      case JointField::Anchor:
        // Default: body 1's position (its own frame's origin in local frames).
        d.anchor = v         ? vec3(*v)
                   : d.local ? Vec3::Zero()
                             : bodies[static_cast<std::size_t>(d.body1.index)].position;
        break;
      case JointField::Axis:
      case JointField::Axis1:
        d.axis = direction(*v);
        break;
      case JointField::Axis2: {
        d.axis2 = direction(*v);
        const double cosine = d.axis.normalized().dot(d.axis2.normalized());
        // In local frames they are in two bodies' frames: the world checks them when it makes it.
        if (!t.uses(JointField::Ratio) && !d.local && std::abs(cosine) > 1e-6)
          fail(v->path, fmt::format("must be perpendicular to axis1 (they are {:.6g} deg apart)",
                                    std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI));
        break;
      }
      case JointField::Length:
        if (v) d.length = positive(*v);
        break;
      case JointField::Rope:
        if (v) d.rope = boolean(*v);
        break;
      case JointField::Cone:
        if (v) {
          allowOnly(*v, {"swing1", "swing2"});
          d.cone =
              ConeLimit{angleBelowPi(require(*v, "swing1")), angleBelowPi(require(*v, "swing2"))};
        }
        break;
      case JointField::Ratio:
        d.ratio = nonZero(*v);
        break;
      case JointField::Axes:
        serialAxes(*v, d);
        break;
      case JointField::Anchor1:  // twoPoints
      case JointField::Anchor2:
      case JointField::Leader:  // coupledJoints
      case JointField::Follower:
      case JointField::Offset:
        break;
    }
  }

  double nonZero(const Node& n) const {
    const double x = number(n);
    if (x == 0.0) fail(n.path, "must not be zero");
    return x;
  }

  // What acts on a joint's free coordinates: its own fields with one, an object per coordinate
  // named as the type names it with several, a serial joint's in each axis (serialAxes).
  void coordinates(const Node& n, const JointTypeInfo& t, JointDef& d) const {
    const int free = t.usesAxes() ? 0 : t.freeCoordinates();
    if (free == 1 && t.coordinates[0].limits_only) {  // a ball joint's angle
      if (auto v = get(n, "limits")) d.coordinates[0].limits = limits(*v);
    } else if (free == 1) {
      d.coordinates[0] = coordinate(n);
    } else {
      for (int i = 0; i < free; ++i)
        if (const auto v = get(n, t.coordinates[static_cast<std::size_t>(i)].name))
          d.coordinates[static_cast<std::size_t>(i)] = record<CoordinateDef>(*v);
    }
  }

  // A mimic joint's leader and follower, by name among the joints before it (the world makes
  // joints in file order, and a joint that ties two needs them made), and its offset.
  void coupledJoints(const Node& n, const std::string& type, std::span<const SceneJoint> earlier,
                     JointDef& d) const {
    const auto find = [&](const char* field) {
      const Node ref = require(n, field);
      const std::string name = string(ref);
      for (std::size_t i = 0; i < earlier.size(); ++i)
        if (earlier[i].def.name == name) return JointId{static_cast<int>(i)};
      fail(ref.path, fmt::format("no joint '{}' before this {} joint (the joints it ties come "
                                 "first in \"joints\")",
                                 name, type));
    };
    d.leader = find("leader");
    d.follower = find("follower");
    if (*d.leader == *d.follower) fail(childPath(n.path, "follower"), "the same joint as leader");
    if (auto v = get(n, "offset")) d.offset = number(*v);
  }

  // A joint's points in local frames, from the frames the file states its bodies in to the bodies'
  // own frames (JointDef::local), which sit at their centres of mass.
  static void inCentreFrames(JointDef& d, std::span<const Vec3> centres) {
    const auto centre = [&](BodyId id) {
      return id.isWorld() ? Vec3::Zero() : centres[static_cast<std::size_t>(id.index)];
    };
    if (d.anchor) *d.anchor -= centre(d.body1);
    if (d.anchor2) *d.anchor2 -= centre(d.body2);
    for (SerialAxis& a : d.axes) a.anchor -= centre(d.body1);
  }

  // A serial joint's axes: each a hinge or a slider, with what acts on its coordinate.
  void serialAxes(const Node& n, JointDef& d) const {
    expectArray(n);
    if (n.value.empty() || n.value.size() > static_cast<std::size_t>(kMaxCoordinates))
      fail(n.path,
           fmt::format("a serial joint has 1 to {} axes, not {}", kMaxCoordinates, n.value.size()));
    for (std::size_t i = 0; i < n.value.size(); ++i) {
      const Node item{n.value[i], itemPath(n.path, i)};
      expectObject(item);
      std::vector<std::string_view> allowed{"type", "axis", "anchor"};
      allowed.insert(allowed.end(), kCoordinateFields.begin(), kCoordinateFields.end());
      allowOnly(item, allowed);
      const Node type = require(item, "type");
      const std::string kind = string(type);
      if (kind != "hinge" && kind != "slider")
        fail(type.path, fmt::format("unknown axis type '{}' (expected hinge or slider)", kind));
      SerialAxis axis;
      axis.linear = kind == "slider";
      axis.axis = direction(require(item, "axis"));
      if (axis.linear) {
        if (item.value.contains("anchor"))
          fail(childPath(item.path, "anchor"), "not used by a slider axis");
      } else {
        axis.anchor = vec3(require(item, "anchor"));
      }
      d.axes.push_back(axis);
      d.coordinates[i] = coordinate(item);
    }
  }

  // A body named in a spring, force or torque.
  BodyId bodyRef(const Node& ref, const std::map<std::string, std::size_t>& body_index,
                 bool world_allowed) const {
    const std::string body = string(ref);
    if (body == "world") {
      if (!world_allowed) fail(ref.path, "must be a body, not the world");
      return kWorldBody;
    }
    const auto it = body_index.find(body);
    if (it == body_index.end()) {
      std::vector<std::string_view> names;
      for (const auto& entry : body_index) names.push_back(entry.first);
      fail(ref.path, fmt::format("unknown body '{}'{}", body, suggestion(body, names)));
    }
    return BodyId{static_cast<int>(it->second)};
  }

  // A top-level spring: a spring joint between two points (docs/scene-format.md, "springs"),
  // whose shapes still collide.
  SceneJoint spring(const Node& n, const std::vector<BodyDef>& bodies,
                    const std::map<std::string, std::size_t>& body_index) const {
    allowOnly(
        n, {"name", "body1", "body2", "anchor1", "anchor2", "stiffness", "damping", "rest_length"});
    SceneJoint joint{"spring", {}};
    JointDef& d = joint.def;
    d.name = n.value.contains("name") ? string(require(n, "name")) : n.path;
    if (d.name.empty()) fail(childPath(n.path, "name"), "must not be empty");
    d.body1 = bodyRef(require(n, "body1"), body_index, false);
    if (auto v = get(n, "body2")) {
      d.body2 = bodyRef(*v, body_index, true);
      if (d.body2 == d.body1) fail(v->path, "a spring needs two different bodies");
    }
    twoPoints(n, bodies, d);
    d.collide = true;
    JointSpring s;
    if (auto v = get(n, "stiffness")) s.stiffness = nonNegative(*v);
    if (auto v = get(n, "damping")) s.damping = nonNegative(*v);
    if (!(s.stiffness > 0.0 || s.damping > 0.0))
      fail(n.path, "needs a stiffness, a damping or both (> 0)");
    s.rest = (*d.anchor - *d.anchor2).norm();
    if (auto v = get(n, "rest_length")) s.rest = nonNegative(*v);
    d.coordinates[0].spring = s;
    return joint;
  }

  // A force (at a point) or a torque on a body, constant or in time.
  LoadDef load(const Node& n, bool force, const std::vector<BodyDef>& bodies,
               const std::map<std::string, std::size_t>& body_index) const {
    if (force)
      allowOnly(n, {"body", "force", "point"});
    else
      allowOnly(n, {"body", "torque"});
    LoadDef load;
    const Node body = require(n, "body");
    load.body = bodyRef(body, body_index, false);
    if (bodies[static_cast<std::size_t>(load.body.index)].is_static)
      fail(body.path, "a static body does not move");
    if (force) {
      load.force = vectorSignal(require(n, "force"));
      if (auto v = get(n, "point")) load.point = vec3(*v);
    } else {
      load.torque = vectorSignal(require(n, "torque"));
    }
    return load;
  }

  // A vector in time: [x, y, z] whose components are numbers or tables (signal), or a table of
  // vectors {"times": [...], "values": [[x, y, z], ...]}.
  VectorSignal vectorSignal(const Node& n) const {
    if (n.value.is_array()) {
      if (n.value.size() != 3)
        fail(n.path, fmt::format("expected 3 components, got {}", n.value.size()));
      std::array<Signal, 3> c;
      for (std::size_t k = 0; k < 3; ++k) c[k] = signal({n.value[k], itemPath(n.path, k)});
      return VectorSignal(c);
    }
    if (!n.value.is_object())
      fail(n.path, fmt::format("expected a vector [x, y, z] or a table {{\"times\": [...], "
                               "\"values\": [[x, y, z], ...]}}, got {}",
                               describe(n.value)));
    allowOnly(n, {"times", "values"});
    const Node times = require(n, "times"), values = require(n, "values");
    expectArray(values);
    std::array<json, 3> columns;
    for (std::size_t i = 0; i < values.value.size(); ++i) {
      const Vec3 v = vec3({values.value[i], itemPath(values.path, i)});
      for (std::size_t k = 0; k < 3; ++k) columns[k].push_back(v[static_cast<Eigen::Index>(k)]);
    }
    std::array<Signal, 3> c;
    for (std::size_t k = 0; k < 3; ++k)
      c[k] = signal({json{{"times", times.value}, {"values", columns[k]}}, n.path});
    return VectorSignal(c);
  }

  // An angle in (0, pi) rad.
  double angleBelowPi(const Node& n) const {
    const double a = number(n);
    if (!(a > 0.0 && a < M_PI)) fail(n.path, fmt::format("must be in (0, pi) rad, got {}", a));
    return a;
  }

  // The two points of a distance or spring joint (default: the bodies' positions).
  void twoPoints(const Node& n, const std::vector<BodyDef>& bodies, JointDef& d) const {
    const auto point = [&](std::string_view key, BodyId body) -> Vec3 {
      if (auto v = get(n, key)) return vec3(*v);
      if (body.isWorld())
        fail(childPath(n.path, key), "missing required field (the point held in the world)");
      return d.local ? Vec3::Zero() : bodies[static_cast<std::size_t>(body.index)].position;
    };
    d.anchor = point("anchor1", d.body1);
    d.anchor2 = point("anchor2", d.body2);
    if (d.local) return;  // the world checks them at the bodies' poses
    const double apart = (*d.anchor - *d.anchor2).norm();
    if (!(apart > 1e-9))
      fail(childPath(n.path, n.value.contains("anchor2") ? "anchor2" : "anchor1"),
           fmt::format("the two points must be apart at the start ({} m; a ball joint joins two "
                       "points)",
                       apart));
  }

  // What acts on a free coordinate: the fields of `n` that a CoordinateDef describes (the others
  // are the joint's, checked by it).
  CoordinateDef coordinate(const Node& n) const {
    CoordinateDef c;
    readFields(n, c, false);
    applyRules(n, c);
    return c;
  }

  JointLimits limits(const Node& n) const { return record<JointLimits>(n); }

  // What a file says more than the C++ API: a rigid velocity motor states its bound, a spring
  // states what it is.
  void fileRules(const Node& n, const JointMotor& m) const {
    if (!m.isServo() && !n.value.contains("max_force"))
      fail(childPath(n.path, "max_force"),
           "missing required field (a velocity motor holds its rate rigidly: give its bound)");
  }
  void fileRules(const Node& n, const JointSpring&) const {
    if (!n.value.contains("stiffness") && !n.value.contains("damping"))
      fail(n.path, "needs a stiffness, a damping or both");
  }
  void fileRules(const Node& n, const ContactSettings& c) const {
    for (const char* key : {"erp", "cfm"})
      if (c.stiffness && n.value.contains(key))
        fail(childPath(n.path, key), "give either erp and cfm, or stiffness and damping");
  }
  template <class R>
  void fileRules(const Node&, const R&) const {}

  // A number, or a table in time: {"times": [...], "values": [...]} or {"file": "CSV"} (two
  // columns, time and value, after an optional header line; relative to the scene file).
  Signal signal(const Node& n) const {
    if (n.value.is_number()) return Signal(number(n));
    if (!n.value.is_object())
      fail(n.path, fmt::format("expected a number or a table {{\"times\": [...], \"values\": "
                               "[...]}}, got {}",
                               describe(n.value)));
    allowOnly(n, {"times", "values", "file"});
    Signal table({}, {});
    if (const auto file = get(n, "file")) {
      const std::string name = string(*file);
      if (name.empty()) fail(file->path, "must not be empty");
      for (std::string_view key : {"times", "values"})
        if (n.value.contains(key))
          fail(childPath(n.path, key), "give either a file or times and values");
      const std::filesystem::path path = std::filesystem::path(file_).parent_path() / name;
      try {
        io::checkInsideFolder(path, std::filesystem::path(file_).parent_path(),
                              options_.allow_outside_paths);
      } catch (const std::runtime_error& e) {
        fail(file->path, e.what());
      }
      table = tableFile(path, file->path);
    } else {
      const auto column = [&](std::string_view key) {
        const Node c = require(n, key);
        expectArray(c);
        std::vector<double> out;
        for (std::size_t i = 0; i < c.value.size(); ++i)
          out.push_back(number({c.value[i], itemPath(c.path, i)}));
        return out;
      };
      table.times = column("times");
      table.values = column("values");
      if (table.times.empty()) fail(childPath(n.path, "times"), "must not be empty");
      if (table.values.size() != table.times.size())
        fail(childPath(n.path, "values"),
             fmt::format("{} values for {} times", table.values.size(), table.times.size()));
      for (std::size_t i = 1; i < table.times.size(); ++i)
        if (!(table.times[i] > table.times[i - 1]))
          fail(itemPath(childPath(n.path, "times"), i),
               fmt::format("must be after the time before it ({} <= {})", table.times[i],
                           table.times[i - 1]));
    }
    return table;
  }

  // Two columns of numbers, time and value, one row per line; the first line may be a header.
  Signal tableFile(const std::filesystem::path& path, const std::string& field) const {
    std::string text;
    try {
      text = io::readInputFile(path, io::kTableLimit, "a table");
    } catch (const std::runtime_error& e) {
      fail(field, fmt::format("cannot read '{}': {}", path.string(), e.what()));
    }
    std::istringstream in(text);
    Signal table({}, {});
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      const auto comma = line.find(',');
      double t = 0.0, v = 0.0;
      // A number between optional blanks (io::finiteNumber).
      const auto parse = [](std::string_view text, double& x) {
        const auto begin = text.find_first_not_of(" \t");
        if (begin == std::string_view::npos) return false;
        const auto number =
            io::finiteNumber(text.substr(begin, text.find_last_not_of(" \t") + 1 - begin));
        if (number) x = *number;
        return number.has_value();
      };
      const bool ok = comma != std::string::npos && parse(line.substr(0, comma), t) &&
                      parse(line.substr(comma + 1), v);
      if (!ok) {
        if (number == 1) continue;  // a header
        fail(field, fmt::format("{} line {}: expected two numbers, time and value, got '{}'",
                                path.string(), number, shownText(line)));
      }
      if (!table.times.empty() && !(t > table.times.back()))
        fail(field, fmt::format("{} line {}: time {} is not after the one before it ({})",
                                path.string(), number, t, table.times.back()));
      table.times.push_back(t);
      table.values.push_back(v);
    }
    if (table.times.empty())
      fail(field, fmt::format("{}: no rows of time and value", path.string()));
    return table;
  }

  const std::string& file_;
  ImportOptions options_;
};

// nlohmann messages start with "[json.exception.parse_error.101] parse error at ".
std::string stripPrefix(const std::string& message, std::string_view marker) {
  const auto at = message.find(marker);
  if (at != std::string::npos) return message.substr(at + marker.size());
  const auto bracket = message.find("] ");
  return bracket == std::string::npos ? message : message.substr(bracket + 2);
}

}  // namespace

Scene parseScene(std::string_view text, const std::string& file, const ImportOptions& options) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos)
    throw SceneError(file, "", "the file is empty (a scene is a JSON object, {...})");
  if (const auto nul = text.find('\0'); nul != std::string_view::npos)
    throw SceneError(file, "",
                     fmt::format("a NUL byte at offset {}: a binary file, not JSON text", nul));
  json root;
  PathTracker tracker(file);
  try {
    root = json::parse(text.begin(), text.end(),
                       [&](int depth, json::parse_event_t event, json& parsed) {
                         return tracker(depth, event, parsed);
                       });
  } catch (const json::parse_error& e) {
    // "line 3, column 5: syntax error while parsing object - unexpected '}'"
    const std::string rest = stripPrefix(e.what(), "parse error at ");
    const auto colon = rest.find(": ");
    if (rest.rfind("line ", 0) == 0 && colon != std::string::npos) {
      throw SceneError(file, rest.substr(0, colon), shownText(rest.substr(colon + 2), 200));
    }
    throw SceneError(file, "(json)", shownText(rest, 200));
  } catch (const json::exception& e) {
    // A number too large for a double: the tracker knows which field it was.
    const std::string path = tracker.current();
    throw SceneError(file, path.empty() ? "(json)" : path, stripPrefix(e.what(), "] "));
  }
  return Reader(file, options).scene(root);
}

Scene loadScene(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string file = path.string();
  std::string text;
  try {
    text = io::readInputFile(path, io::kSceneLimit, "a scene");
  } catch (const std::runtime_error& e) {
    throw SceneError(file, "", e.what());
  }
  return parseScene(text, file, options);
}

}  // namespace linx
