// URDF robots as scenes (docs/model-import.md). urdfdom reads the model; tinyxml2 walks the same
// text once more to name what urdfdom reads but linx does not use (transmissions, Gazebo tags,
// mimic joints, ...), so that nothing is dropped silently.
//
// Frames: a link's frame is its parent joint's frame at the joint's zero position (URDF's rule),
// placed in the world from the root at the origin. A body's frame is its link's frame moved to
// the link's centre of mass (the inertial origin); its inertia is turned into the link's axes.
// Shapes are placed relative to the body that carries them, which for a massless link joined by a
// fixed joint is its parent's body.
#include <linx/import.hpp>

#include "io/import_check.hpp"
#include "io/input_file.hpp"
#include "io/mesh_file.hpp"
#include "io/mimic_cycles.hpp"
#include "io/xml_error.hpp"

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <locale>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace linx {
namespace {

// Shapes of one robot do not collide with each other (self-collision off, as in PyBullet's
// default): group 2, and a mask without it. They collide with everything else.
constexpr std::uint32_t kRobotGroup = 2;

// urdfdom reports why a file is refused through console_bridge; this keeps the first error.
class ErrorCapture : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first.empty()) first = text;
  }
  std::string first;
};

Vec3 toVec3(const urdf::Vector3& v) {
  return {v.x, v.y, v.z};
}

Pose toPose(const urdf::Pose& p) {
  const urdf::Rotation& r = p.rotation;
  return {toVec3(p.position), Quat(r.w, r.x, r.y, r.z).normalized()};
}

Pose compose(const Pose& a, const Pose& b) {  // b given in a's frame
  return {a.toWorld(b.position), (a.orientation * b.orientation).normalized()};
}

// What the file holds that linx does not use, counted by name ("<transmission>", ...).
class Unsupported {
 public:
  void add(const std::string& what) { ++counts_[what]; }
  std::vector<std::string> warnings(const std::string& file) const {
    if (counts_.empty()) return {};
    std::string list;
    for (const auto& [what, count] : counts_)
      list += fmt::format("{}{}{}", list.empty() ? "" : ", ", what,
                          count > 1 ? fmt::format(" (x{})", count) : "");
    return {fmt::format("{}: not used by linx, ignored: {}", file, list)};
  }

 private:
  std::map<std::string, int> counts_;
};

// The XML elements and attributes linx does not use, and the links' and joints' order in the file.
struct XmlSurvey {
  std::vector<std::string> links, joints;
  Unsupported unsupported;
};

// URDF's numbers, checked before urdfdom reads them (urdfdom's own message names neither the
// element nor its joint or link, and it takes some faults silently: a box of two numbers is
// dropped). A number is a decimal as urdfdom reads it (no hex, inf or nan), and finite.
class NumberCheck {
 public:
  explicit NumberCheck(const std::string& file) : file_(file) {}

  // The numbers of `attribute` of `e` (none when it is absent and not `required`): `count` of
  // them, each finite, and > 0 when `positive`. `owner` names e's joint or link.
  std::vector<double> numbers(const tinyxml2::XMLElement* e, const std::string& owner,
                              const char* attribute, std::size_t count, bool required = false,
                              bool positive = false) const {
    const char* text = e->Attribute(attribute);
    if (!text) {
      if (required) fail(e, owner, fmt::format("{}: missing", attribute));
      return {};
    }
    std::vector<double> out;
    std::vector<std::string> words;
    std::istringstream in(text);
    for (std::string word; in >> word;) {
      const std::optional<double> v = number(word);
      if (!v) fail(e, owner, fmt::format("{}: '{}' is not a finite number", attribute, word));
      out.push_back(*v);
      words.push_back(word);
    }
    const bool all_positive = std::all_of(out.begin(), out.end(), [](double v) { return v > 0; });
    if (positive && (out.size() != count || !all_positive)) {
      std::string got;
      for (const std::string& w : words) got += (got.empty() ? "" : " ") + w;
      fail(e, owner,
           count == 1 ? fmt::format("{}: must be a number > 0, got {}", attribute,
                                    got.empty() ? "nothing" : got)
                      : fmt::format("{}: must be {} numbers > 0, got {}", attribute, count,
                                    got.empty() ? "nothing" : got));
    }
    if (out.size() != count)
      fail(e, owner,
           fmt::format("{}: needs {} number{}, got {}", attribute, count, count == 1 ? "" : "s",
                       out.size()));
    return out;
  }

  // A link's or joint's elements and their numbers (the URDF spec's, as urdfdom reads them).
  void link(const tinyxml2::XMLElement* link, const std::string& name) const {
    const std::string owner = fmt::format("link '{}'", name);
    if (const auto* inertial = link->FirstChildElement("inertial")) {
      origin(inertial, owner);
      if (const auto* mass = inertial->FirstChildElement("mass"))
        numbers(mass, owner, "value", 1, /*required=*/true);
      if (const auto* inertia = inertial->FirstChildElement("inertia"))
        for (const char* a : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"})
          numbers(inertia, owner, a, 1, /*required=*/true);
    }
    for (const char* kind : {"collision", "visual"}) {
      int index = 0;
      for (const auto* c = link->FirstChildElement(kind); c;
           c = c->NextSiblingElement(kind), ++index) {
        const std::string where = fmt::format("{} {} {}", owner, kind, index);
        origin(c, where);
        if (std::string(kind) == "collision")
          geometry(c, where, /*collision=*/true);
        else if (c->FirstChildElement("geometry"))  // visuals are not used: only read
          geometry(c, where, /*collision=*/false);
      }
    }
  }

  void joint(const tinyxml2::XMLElement* joint, const std::string& name) const {
    const std::string owner = fmt::format("joint '{}'", name);
    origin(joint, owner);
    if (const auto* axis = joint->FirstChildElement("axis")) numbers(axis, owner, "xyz", 3);
    if (const auto* limit = joint->FirstChildElement("limit")) {
      for (const char* a : {"lower", "upper"}) numbers(limit, owner, a, 1);
      for (const char* a : {"effort", "velocity"})  // URDF requires them; linx does not use them
        numbers(limit, owner, a, 1, /*required=*/true);
    }
    if (const auto* dynamics = joint->FirstChildElement("dynamics"))
      for (const char* a : {"damping", "friction"}) numbers(dynamics, owner, a, 1);
    if (const auto* mimic = joint->FirstChildElement("mimic"))
      for (const char* a : {"multiplier", "offset"}) numbers(mimic, owner, a, 1);
    if (const auto* safety = joint->FirstChildElement("safety_controller"))
      for (const char* a : {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"})
        numbers(safety, owner, a, 1);
    if (const auto* calibration = joint->FirstChildElement("calibration"))
      for (const char* a : {"rising", "falling"}) numbers(calibration, owner, a, 1);
  }

 private:
  // As urdfdom's strToDouble reads a number (the C locale's decimal, an optional sign).
  static std::optional<double> number(const std::string& word) {
    std::istringstream in(word);
    in.imbue(std::locale::classic());
    double v = 0.0;
    if (!(in >> v) || in.peek() != std::char_traits<char>::eof() || !std::isfinite(v))
      return std::nullopt;
    return v;
  }

  void origin(const tinyxml2::XMLElement* parent, const std::string& owner) const {
    if (const auto* o = parent->FirstChildElement("origin")) {
      numbers(o, owner, "xyz", 3);
      numbers(o, owner, "rpy", 3);
    }
  }

  // A collision's or visual's <geometry>: a collision's sizes must be > 0 (a visual's are only
  // read). urdfdom drops a collision without a shape it knows, silently.
  void geometry(const tinyxml2::XMLElement* parent, const std::string& owner,
                bool collision) const {
    const auto* g = parent->FirstChildElement("geometry");
    if (!g) fail(parent, owner, "needs a <geometry>");
    const auto* shape = g->FirstChildElement();
    const std::string type = shape ? shape->Name() : "";
    if (collision && type != "box" && type != "sphere" && type != "cylinder" && type != "mesh")
      fail(g, owner,
           type.empty()
               ? "needs a box, sphere, cylinder or mesh"
               : fmt::format("<{}> is not a URDF geometry (box, sphere, cylinder, mesh)", type));
    if (type == "box") {
      numbers(shape, owner, "size", 3, /*required=*/true, collision);
    } else if (type == "sphere") {
      numbers(shape, owner, "radius", 1, /*required=*/true, collision);
    } else if (type == "cylinder") {
      numbers(shape, owner, "radius", 1, /*required=*/true, collision);
      numbers(shape, owner, "length", 1, /*required=*/true, collision);
    } else if (type == "mesh") {
      if (collision && !shape->Attribute("filename")) fail(shape, owner, "filename: missing");
      const std::vector<double> scale = numbers(shape, owner, "scale", 3);
      if (std::find(scale.begin(), scale.end(), 0.0) != scale.end())
        fail(shape, owner,
             fmt::format("scale: must be 3 non-zero numbers, got {}", shape->Attribute("scale")));
    }
  }

  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& owner,
                         const std::string& problem) const {
    throw SceneError(file_, fmt::format("{} <{}> (line {})", owner, e->Name(), e->GetLineNum()),
                     problem);
  }

  std::string file_;
};

// What urdfdom refuses with a message naming no line ("Joint [yaw] has no known type
// [spherical]"), said first with the element and its line: names (present, links' unique),
// joint types, a revolute or prismatic joint's <limit>, the links a joint names.
void checkStructure(const tinyxml2::XMLElement* robot, const std::string& file) {
  const auto fail = [&](const tinyxml2::XMLElement* e, const std::string& owner,
                        const std::string& problem) {
    throw SceneError(file, fmt::format("{} (line {})", owner, e->GetLineNum()), problem);
  };
  std::map<std::string, int> links;  // name, line
  for (auto* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
    const char* name = e->Attribute("name");
    if (!name || !*name) fail(e, "link", "name: missing");
    const auto [at, added] = links.emplace(name, e->GetLineNum());
    if (!added)
      fail(e, fmt::format("link '{}'", name),
           fmt::format("name: another link has it (line {})", at->second));
  }
  std::set<std::string> joints;
  for (auto* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
    const char* name = e->Attribute("name");
    if (!name || !*name) fail(e, "joint", "name: missing");
    const std::string owner = fmt::format("joint '{}'", name);
    if (!joints.insert(name).second) fail(e, owner, "name: another joint has it");
    const std::string type = e->Attribute("type") ? e->Attribute("type") : "";
    static const std::set<std::string> kTypes = {"revolute", "continuous", "prismatic",
                                                 "fixed",    "floating",   "planar"};
    if (!kTypes.contains(type))
      fail(e, owner,
           type.empty() ? "type: missing"
                        : fmt::format("type: '{}' is not a URDF joint type (revolute, continuous, "
                                      "prismatic, fixed, floating, planar)",
                                      type));
    if ((type == "revolute" || type == "prismatic") && !e->FirstChildElement("limit"))
      fail(e, owner,
           fmt::format("a {} joint needs a <limit> (lower, upper, effort, velocity)", type));
    for (const char* end : {"parent", "child"}) {
      const tinyxml2::XMLElement* ref = e->FirstChildElement(end);
      const char* link = ref ? ref->Attribute("link") : nullptr;
      if (!link) fail(e, owner, fmt::format("<{} link=...>: missing", end));
      if (!links.contains(link))
        fail(ref, owner + " <" + end + ">", fmt::format("link: no link '{}'", link));
    }
  }
}

XmlSurvey survey(const std::string& text, const std::string& file) {
  tinyxml2::XMLDocument doc;
  io::parseXml(doc, text, file);
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw SceneError(file, "robot", "a URDF file needs a <robot> element");
  XmlSurvey s;
  const NumberCheck check(file);
  for (auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Name();
    const char* name = e->Attribute("name");
    if (tag == "link") {
      if (name) s.links.emplace_back(name);
      check.link(e, name ? name : "");
      for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
        const std::string child = c->Name();
        if (child == "visual")
          s.unsupported.add("<visual> (drawn as the collision shapes)");
        else if (child != "inertial" && child != "collision")
          s.unsupported.add("<" + child + ">");
      }
    } else if (tag == "joint") {
      if (name) s.joints.emplace_back(name);
      check.joint(e, name ? name : "");
      for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
        const std::string child = c->Name();
        if (child == "limit") {
          if (c->Attribute("effort") || c->Attribute("velocity"))
            s.unsupported.add("joint limit effort and velocity (no actuators)");
        } else if (child != "origin" && child != "parent" && child != "child" && child != "axis" &&
                   child != "dynamics" && child != "mimic") {
          s.unsupported.add("<" + child + "> in a joint");
        }
      }
    } else if (tag != "material") {
      s.unsupported.add("<" + tag + ">");
    }
  }
  checkStructure(robot, file);
  return s;
}

urdf::ModelInterfaceSharedPtr parse(const std::string& text, const std::string& file) {
  static std::mutex mutex;  // console_bridge's handler is global
  const std::lock_guard lock(mutex);
  ErrorCapture capture;
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    capture.first = capture.first.empty() ? e.what() : capture.first;
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model)
    throw SceneError(file, "robot",
                     capture.first.empty() ? "urdfdom could not read it" : capture.first);
  return model;
}

// "package://pkg/meshes/a.stl" and "file:///abs/a.stl" to a file, and the folder it must lie in
// (unless outside paths are allowed): a package is looked for as a folder named pkg in the URDF's
// folder and its parents (a ROS workspace's layout), and its files lie in it; every other file
// lies in the URDF's folder.
struct MeshFile {
  std::filesystem::path file, folder;
};

// Throws std::runtime_error when the package is not found.
MeshFile meshPath(const std::string& uri, const std::filesystem::path& urdf_dir) {
  constexpr std::string_view package = "package://", file = "file://";
  if (uri.rfind(file, 0) == 0) return {uri.substr(file.size()), urdf_dir};
  if (uri.rfind(package, 0) != 0) return {urdf_dir / uri, urdf_dir};
  const std::string rest = uri.substr(package.size());
  const std::size_t slash = rest.find('/');
  const std::string name = rest.substr(0, slash);
  const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
  if (name.empty() || name == "." || name == "..")
    throw std::runtime_error(fmt::format("mesh file '{}': no package name after package://", uri));
  std::error_code error;  // an unreadable folder on the way up counts as no package there
  const std::filesystem::path start = urdf_dir.empty()  // a URDF in the working folder
                                          ? std::filesystem::current_path(error)
                                          : std::filesystem::absolute(urdf_dir, error);
  for (std::filesystem::path dir = start; !dir.empty(); dir = dir.parent_path()) {
    if (dir.filename() == name) return {dir / inside, dir};
    if (std::filesystem::is_directory(dir / name, error)) return {dir / name / inside, dir / name};
    if (dir == dir.parent_path()) break;
  }
  throw std::runtime_error(
      fmt::format("mesh file '{}': package '{}' not found (linx looks for a folder named {} in {} "
                  "and the folders above it)",
                  uri, name, name, start.empty() ? urdf_dir.string() : start.string()));
}

class UrdfImporter {
 public:
  UrdfImporter(const std::filesystem::path& path, const ImportOptions& options)
      : path_(path), file_(path.string()), options_(options) {}
  // A URDF whose joints form a loop leaves urdfdom's links owning one another in a ring (each
  // holds its children): broken here, or the model is never freed (found by fuzz_model).
  ~UrdfImporter() {
    if (!model_) return;
    for (auto& [name, link] : model_->links_) {
      if (!link) continue;
      link->child_links.clear();
      link->child_joints.clear();
    }
  }
  UrdfImporter(const UrdfImporter&) = delete;
  UrdfImporter& operator=(const UrdfImporter&) = delete;

  Scene run() {
    const std::string text = readText();
    XmlSurvey xml = survey(text, file_);
    model_ = parse(text, file_);
    place(model_->getRoot(), Pose{}, /*owner=*/"");
    for (const std::string& name : xml.links)
      if (!frame_.count(name)) failLoop(name, xml.joints);
    Scene scene;
    scene.file = file_;
    for (const std::string& name : xml.links)
      if (ownerOf(name) == name) scene.bodies.push_back(body(name));
    for (const std::string& name : xml.links) attachShapes(name, scene);
    for (const std::string& name : xml.joints)
      if (auto joint = makeJoint(jointOf(name), scene)) scene.joints.push_back(*joint);
    // Mimic joints after the joints they tie (a scene names them before).
    for (const std::string& name : xml.joints)
      if (const urdf::Joint& j = jointOf(name); j.mimic) scene.joints.push_back(mimic(j, scene));
    if (const auto cycle = io::findMimicCycle(scene)) {
      const JointDef& d = scene.joints[cycle->mimic].def;
      fail(fmt::format("joint '{}' <mimic>",
                       scene.joints[static_cast<std::size_t>(d.follower->index)].def.name),
           cycle->problem);
    }
    io::completeImported(scene, "link");
    scene.warnings = xml.unsupported.warnings(file_);
    if (!meshes_made_convex_.empty()) scene.warnings.push_back(convexMeshesWarning());
    if (!started_outside_.empty())
      scene.warnings.push_back(
          fmt::format("{}: {}", file_, io::startOutsideWarning(started_outside_)));
    return scene;
  }

 private:
  std::string readText() const {
    try {
      return io::readInputFile(path_, io::kModelLimit, "a URDF file");
    } catch (const std::runtime_error& e) {
      throw SceneError(file_, "", e.what());
    }
  }

  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw SceneError(file_, where, problem);
  }

  // A link that the root does not reach: urdfdom takes a loop of joints (each link has one
  // parent, so it finds a root elsewhere), but a URDF is a tree. Names the loop, from the joint
  // that comes first in the file.
  [[noreturn]] void failLoop(const std::string& unreached,
                             const std::vector<std::string>& joint_order) const {
    std::vector<const urdf::Joint*> path;  // parent joints, from `unreached` up
    for (urdf::LinkConstSharedPtr link = model_->getLink(unreached); link && link->parent_joint;
         link = model_->getLink(link->parent_joint->parent_link_name)) {
      const urdf::Joint* joint = link->parent_joint.get();
      const auto seen = std::find(path.begin(), path.end(), joint);
      if (seen == path.end()) {
        path.push_back(joint);
        continue;
      }
      std::vector<const urdf::Joint*> loop(seen, path.end());  // child to parent
      std::reverse(loop.begin(), loop.end());                  // parent to child
      const auto first = std::min_element(loop.begin(), loop.end(), [&](auto* a, auto* b) {
        const auto place = [&](const urdf::Joint* j) {
          return std::find(joint_order.begin(), joint_order.end(), j->name) - joint_order.begin();
        };
        return place(a) < place(b);
      });
      std::rotate(loop.begin(), first, loop.end());
      std::string joints, links = loop.front()->parent_link_name;
      for (const urdf::Joint* j : loop) {
        joints += fmt::format("{}'{}'", joints.empty() ? "" : ", ", j->name);
        links += " -> " + j->child_link_name;
      }
      fail("robot", fmt::format("joints {} form a loop ({}): a URDF's links must form a tree",
                                joints, links));
    }
    fail(fmt::format("link '{}'", unreached),
         fmt::format("not connected to the root link '{}'", model_->getRoot()->name));
  }

  // A placed link's frame and the link whose body carries it (place() reached every link).
  const Pose& frameOf(const std::string& link) const {
    const auto found = frame_.find(link);
    if (found == frame_.end()) fail(fmt::format("link '{}'", link), "internal: not placed");
    return found->second;
  }

  const urdf::Link& linkOf(const std::string& name) const {
    const urdf::LinkConstSharedPtr link = model_->getLink(name);
    if (!link) fail(fmt::format("link '{}'", name), "internal: urdfdom did not read it");
    return *link;
  }

  const urdf::Joint& jointOf(const std::string& name) const {
    const urdf::JointConstSharedPtr joint = model_->getJoint(name);
    if (!joint) fail(fmt::format("joint '{}'", name), "internal: urdfdom did not read it");
    return *joint;
  }

  const std::string& ownerOf(const std::string& link) const {
    const auto found = owner_.find(link);
    if (found == owner_.end()) fail(fmt::format("link '{}'", link), "internal: not placed");
    return found->second;
  }

  static bool hasMass(const urdf::Link& link) { return link.inertial && link.inertial->mass > 0.0; }

  // Each link's frame in the world, and the link whose body carries it (itself, or for a
  // massless link on a fixed joint its parent's carrier).
  void place(const urdf::LinkConstSharedPtr& link, const Pose& frame, const std::string& parent) {
    // urdfdom links a child of two parents into both: the walk would go round the loop for ever.
    if (frame_.count(link->name))
      fail(fmt::format("link '{}'", link->name),
           "reached a second time: the joints form a loop (a URDF's links form a tree)");
    frame_[link->name] = frame;
    const bool root = parent.empty();
    const urdf::JointConstSharedPtr& joint = link->parent_joint;
    if (root && link->name == "world" && !options_.floating_base) {
      owner_[link->name] = "";  // URDF's convention: the world frame itself
    } else if (root) {
      if (options_.floating_base && !hasMass(*link))
        fail(fmt::format("link '{}'", link->name),
             "the root link of a floating base needs an <inertial> with a mass > 0");
      owner_[link->name] = link->name;
    } else if (hasMass(*link)) {
      owner_[link->name] = link->name;
    } else if (joint->type == urdf::Joint::FIXED) {
      owner_[link->name] = ownerOf(parent);
    } else {
      fail(fmt::format("link '{}'", link->name),
           fmt::format("has no <inertial> with a mass > 0, but joint '{}' moves it", joint->name));
    }
    for (const urdf::LinkSharedPtr& child : link->child_links) {
      const Pose joint_frame = toPose(child->parent_joint->parent_to_joint_origin_transform);
      place(child, compose(frame, joint_frame), link->name);
    }
  }

  bool isStatic(const std::string& link) const {
    return link == model_->getRoot()->name && !options_.floating_base;
  }

  BodyDef body(const std::string& name) const {
    const urdf::Link& link = linkOf(name);
    const Pose& frame = frameOf(name);
    BodyDef def;
    def.name = name;
    def.orientation = frame.orientation;
    def.position = frame.position;
    if (isStatic(name)) {
      def.is_static = true;
      return def;
    }
    const urdf::Inertial& in = *link.inertial;
    const Pose inertial = toPose(in.origin);
    Mat3 inertia;
    inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Mat3 r = inertial.orientation.toRotationMatrix();
    def.mass = in.mass;
    def.inertia = r * inertia * r.transpose();  // in the link's axes
    def.position = frame.toWorld(inertial.position);
    return def;
  }

  // Where the body carrying `link` is, as its BodyDef says.
  Pose bodyPose(const std::string& link, const Scene& scene) const {
    const std::string& owner = ownerOf(link);
    if (owner.empty()) return Pose{};
    for (const BodyDef& b : scene.bodies)
      if (b.name == owner) return {b.position, b.orientation};
    fail(fmt::format("link '{}'", link), "internal: no body carries it");
  }

  int bodyIndex(const std::string& link, const Scene& scene) const {
    const std::string& owner = ownerOf(link);
    if (owner.empty()) return -1;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      if (scene.bodies[i].name == owner) return static_cast<int>(i);
    return -1;
  }

  void attachShapes(const std::string& name, Scene& scene) {
    const urdf::Link& link = linkOf(name);
    if (link.collision_array.empty()) return;
    int index = bodyIndex(name, scene);
    const Pose carrier = bodyPose(name, scene);
    if (index < 0) index = worldShapesBody(scene);  // shapes on the world frame
    BodyDef& body = scene.bodies[static_cast<std::size_t>(index)];
    for (std::size_t i = 0; i < link.collision_array.size(); ++i) {
      const urdf::Collision& c = *link.collision_array[i];
      const std::string where = fmt::format("link '{}' collision {}", name, i);
      if (!c.geometry) fail(where, "has no <geometry>");
      ShapeDef s = shape(*c.geometry, where, body.is_static);
      const Pose world = compose(frameOf(name), toPose(c.origin));
      s.position = carrier.toLocal(world.position);
      s.orientation = (carrier.orientation.conjugate() * world.orientation).normalized();
      s.group = kRobotGroup;
      s.mask = ~kRobotGroup;
      body.shapes.push_back(std::move(s));
    }
  }

  // A static body for shapes fixed to the world frame (a root link named "world", and massless
  // links fixed to it): "world" names the frame itself in a scene.
  static int worldShapesBody(Scene& scene) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      if (scene.bodies[i].name == "world_shapes") return static_cast<int>(i);
    BodyDef def;
    def.name = "world_shapes";
    def.is_static = true;
    scene.bodies.push_back(def);
    return static_cast<int>(scene.bodies.size()) - 1;
  }

  ShapeDef shape(const urdf::Geometry& g, const std::string& where, bool on_static) {
    ShapeDef s;
    switch (g.type) {
      case urdf::Geometry::SPHERE:
        s.type = ShapeType::Sphere;
        s.radius = static_cast<const urdf::Sphere&>(g).radius;
        break;
      case urdf::Geometry::BOX:
        s.type = ShapeType::Box;
        s.size = toVec3(static_cast<const urdf::Box&>(g).dim);
        break;
      case urdf::Geometry::CYLINDER: {
        const auto& c = static_cast<const urdf::Cylinder&>(g);
        s.type = ShapeType::Cylinder;
        s.radius = c.radius;
        s.length = c.length;
        break;
      }
      case urdf::Geometry::MESH: {
        const auto& m = static_cast<const urdf::Mesh&>(g);
        try {
          const MeshFile mesh = meshPath(m.filename, path_.parent_path());
          io::checkInsideFolder(mesh.file, mesh.folder, options_.allow_outside_paths);
          s = io::loadMeshFile(mesh.file.string());
        } catch (const std::exception& e) {
          fail(where, e.what());
        }
        const Vec3 scale = toVec3(m.scale);
        for (Vec3& p : s.points) p = p.cwiseProduct(scale);
        s.file = m.filename;
        if (!on_static) {  // moving bodies collide through convex shapes
          s.type = ShapeType::Convex;
          s.triangles.clear();
          meshes_made_convex_.push_back(fmt::format("{} ('{}')", where, m.filename));
        }
        break;
      }
    }
    return s;
  }

  // <mimic joint="leader" multiplier="r" offset="c">: this joint's value is r times the leader's
  // plus c (both in URDF's sense, which the hinges and sliders made here keep).
  SceneJoint mimic(const urdf::Joint& j, const Scene& scene) const {
    const std::string where = fmt::format("joint '{}' <mimic>", j.name);
    const auto index = [&](const std::string& name) -> std::optional<JointId> {
      for (std::size_t i = 0; i < scene.joints.size(); ++i)
        if (scene.joints[i].def.name == name) return JointId{static_cast<int>(i)};
      return std::nullopt;
    };
    const std::string& leader = j.mimic->joint_name;
    SceneJoint out;
    out.type = "mimic";
    out.def.name = j.name + ".mimic";
    out.def.follower = index(j.name);
    out.def.leader = index(leader);
    if (!model_->getJoint(leader)) fail(where, fmt::format("no joint '{}' to follow", leader));
    for (const auto& [name, id] :
         {std::pair{j.name, out.def.follower}, std::pair{leader, out.def.leader}})
      if (!id || (scene.joints[static_cast<std::size_t>(id->index)].type != "hinge" &&
                  scene.joints[static_cast<std::size_t>(id->index)].type != "slider"))
        fail(where, fmt::format("joint '{}' is not a revolute, continuous or prismatic joint of a "
                                "moving link: a mimic ties two of those",
                                name));
    out.def.ratio = j.mimic->multiplier;
    out.def.offset = j.mimic->offset;
    if (!std::isfinite(out.def.ratio) || out.def.ratio == 0.0 || !std::isfinite(out.def.offset))
      fail(where, "multiplier must be finite and non-zero, offset finite");
    return out;
  }

  std::optional<SceneJoint> makeJoint(const urdf::Joint& j, const Scene& scene) {
    if (j.type == urdf::Joint::FLOATING) return std::nullopt;  // the child moves freely
    if (ownerOf(j.child_link_name) != j.child_link_name) return std::nullopt;  // merged
    const std::string where = fmt::format("joint '{}'", j.name);
    const Pose& frame = frameOf(j.child_link_name);  // the joint's frame at zero
    SceneJoint out;
    JointDef& def = out.def;
    def.name = j.name;
    def.body1 = BodyId{bodyIndex(j.child_link_name, scene)};
    def.body2 = BodyId{bodyIndex(j.parent_link_name, scene)};
    def.anchor = frame.position;
    const Vec3 axis = frame.orientation * toVec3(j.axis);
    const bool uses_axis = j.type != urdf::Joint::FIXED;
    if (uses_axis && !(axis.norm() > 1e-12)) fail(where, "<axis> must not be zero");
    if (uses_axis) def.axis = axis.normalized();
    CoordinateDef& coordinate = def.coordinates[0];
    switch (j.type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::PRISMATIC:
        out.type = j.type == urdf::Joint::REVOLUTE ? "hinge" : "slider";
        if (j.limits) {
          if (!(j.limits->lower <= j.limits->upper))
            fail(where, fmt::format("<limit> lower {} is above upper {}", j.limits->lower,
                                    j.limits->upper));
          coordinate.limits = JointLimits{j.limits->lower, j.limits->upper};
          if (auto moved =
                  io::startInsideLimits(coordinate, j.name, j.type == urdf::Joint::REVOLUTE))
            started_outside_.push_back(*moved);
        }
        break;
      case urdf::Joint::CONTINUOUS:
        out.type = "hinge";
        break;
      case urdf::Joint::FIXED:
        out.type = "fixed";
        break;
      case urdf::Joint::PLANAR: {  // `axis` is the plane's normal
        out.type = "planar";
        const Vec3 normal = def.axis;
        const Vec3 x = normal.unitOrthogonal();
        def.axis = x;
        def.axis2 = normal.cross(x);
        break;
      }
      default:
        fail(where, "has an unknown type");
    }
    if (j.dynamics && (out.type == "hinge" || out.type == "slider")) {
      if (!(j.dynamics->damping >= 0.0) || !(j.dynamics->friction >= 0.0))
        fail(where, "<dynamics> damping and friction must be >= 0");
      if (j.dynamics->damping > 0.0) coordinate.spring = JointSpring{0.0, j.dynamics->damping, 0.0};
      coordinate.friction = j.dynamics->friction;
    }
    return out;
  }

  std::filesystem::path path_;
  std::string file_;
  ImportOptions options_;
  urdf::ModelInterfaceSharedPtr model_;
  std::map<std::string, Pose> frame_;
  std::map<std::string, std::string> owner_;
  std::vector<std::string> meshes_made_convex_;    // where each is, and its file
  std::vector<io::StartOutside> started_outside_;  // joints moved inside their range

  /// One warning for every mesh on a moving link: they collide as their convex hulls (the first
  /// few named).
  std::string convexMeshesWarning() const {
    constexpr std::size_t kNamed = 4;
    const std::size_t n = meshes_made_convex_.size();
    std::string list;
    for (std::size_t k = 0; k < std::min(n, kNamed); ++k)
      list += (k ? ", " : "") + meshes_made_convex_[k];
    if (n > kNamed) list += fmt::format(" and {} more", n - kNamed);
    return fmt::format(
        "{}: {} mesh{} on moving links collide{} as {} convex hull{} (linx's moving "
        "bodies collide through convex shapes): {}",
        file_, n, n == 1 ? "" : "es", n == 1 ? "s" : "", n == 1 ? "its" : "their",
        n == 1 ? "" : "s", list);
  }
};

}  // namespace

Scene importUrdf(const std::filesystem::path& path, const ImportOptions& options) {
  return UrdfImporter(path, options).run();
}

}  // namespace linx
