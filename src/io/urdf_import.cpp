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

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
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

XmlSurvey survey(const std::string& text, const std::string& file) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS)
    throw SceneError(file, fmt::format("line {}", doc.ErrorLineNum()),
                     fmt::format("not well-formed XML: {}", doc.ErrorStr()));
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw SceneError(file, "robot", "a URDF file needs a <robot> element");
  XmlSurvey s;
  for (auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Name();
    const char* name = e->Attribute("name");
    if (tag == "link") {
      if (name) s.links.emplace_back(name);
      for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
        const std::string child = c->Name();
        if (child == "visual")
          s.unsupported.add("<visual> (drawn as the collision shapes)");
        else if (child != "inertial" && child != "collision")
          s.unsupported.add("<" + child + ">");
      }
    } else if (tag == "joint") {
      if (name) s.joints.emplace_back(name);
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

MeshFile meshPath(const std::string& uri, const std::filesystem::path& urdf_dir) {
  constexpr std::string_view package = "package://", file = "file://";
  if (uri.rfind(file, 0) == 0) return {uri.substr(file.size()), urdf_dir};
  if (uri.rfind(package, 0) != 0) return {urdf_dir / uri, urdf_dir};
  const std::string rest = uri.substr(package.size());
  const std::size_t slash = rest.find('/');
  const std::string name = rest.substr(0, slash);
  const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
  for (std::filesystem::path dir = std::filesystem::absolute(urdf_dir); !dir.empty();
       dir = dir.parent_path()) {
    if (dir.filename() == name) return {dir / inside, dir};
    if (std::filesystem::is_directory(dir / name)) return {dir / name / inside, dir / name};
    if (dir == dir.parent_path()) break;
  }
  return {urdf_dir / inside, urdf_dir};  // not found: the message names this path
}

class UrdfImporter {
 public:
  UrdfImporter(const std::filesystem::path& path, const ImportOptions& options)
      : path_(path), file_(path.string()), options_(options) {}

  Scene run() {
    const std::string text = readText();
    XmlSurvey xml = survey(text, file_);
    model_ = parse(text, file_);
    place(model_->getRoot(), Pose{}, /*owner=*/"");
    Scene scene;
    scene.file = file_;
    for (const std::string& name : xml.links)
      if (owner_.at(name) == name) scene.bodies.push_back(body(name));
    for (const std::string& name : xml.links) attachShapes(name, scene);
    for (const std::string& name : xml.joints)
      if (auto joint = makeJoint(*model_->getJoint(name), scene)) scene.joints.push_back(*joint);
    // Mimic joints after the joints they tie (a scene names them before).
    for (const std::string& name : xml.joints)
      if (const urdf::Joint& j = *model_->getJoint(name); j.mimic)
        scene.joints.push_back(mimic(j, scene));
    io::completeImported(scene, "link");
    scene.warnings = xml.unsupported.warnings(file_);
    for (const std::string& w : meshes_made_convex_) scene.warnings.push_back(w);
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

  static bool hasMass(const urdf::Link& link) { return link.inertial && link.inertial->mass > 0.0; }

  // Each link's frame in the world, and the link whose body carries it (itself, or for a
  // massless link on a fixed joint its parent's carrier).
  void place(const urdf::LinkConstSharedPtr& link, const Pose& frame, const std::string& parent) {
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
      owner_[link->name] = owner_.at(parent);
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
    const urdf::Link& link = *model_->getLink(name);
    const Pose& frame = frame_.at(name);
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
    const std::string& owner = owner_.at(link);
    if (owner.empty()) return Pose{};
    for (const BodyDef& b : scene.bodies)
      if (b.name == owner) return {b.position, b.orientation};
    fail(fmt::format("link '{}'", link), "internal: no body carries it");
  }

  int bodyIndex(const std::string& link, const Scene& scene) const {
    const std::string& owner = owner_.at(link);
    if (owner.empty()) return -1;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      if (scene.bodies[i].name == owner) return static_cast<int>(i);
    return -1;
  }

  void attachShapes(const std::string& name, Scene& scene) {
    const urdf::Link& link = *model_->getLink(name);
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
      const Pose world = compose(frame_.at(name), toPose(c.origin));
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
        const MeshFile mesh = meshPath(m.filename, path_.parent_path());
        try {
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
          meshes_made_convex_.push_back(fmt::format("{}: {}: mesh '{}' collides as its convex hull",
                                                    file_, where, m.filename));
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

  std::optional<SceneJoint> makeJoint(const urdf::Joint& j, const Scene& scene) const {
    if (j.type == urdf::Joint::FLOATING) return std::nullopt;  // the child moves freely
    if (owner_.at(j.child_link_name) != j.child_link_name) return std::nullopt;  // merged
    const std::string where = fmt::format("joint '{}'", j.name);
    const Pose& frame = frame_.at(j.child_link_name);  // the joint's frame at zero
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
  std::vector<std::string> meshes_made_convex_;
};

}  // namespace

Scene importUrdf(const std::filesystem::path& path, const ImportOptions& options) {
  return UrdfImporter(path, options).run();
}

}  // namespace linx
