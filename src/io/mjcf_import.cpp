// MuJoCo MJCF models as scenes (docs/model-import.md, "MJCF"): a subset read with tinyxml2.
//
// The steps: splice <include> files in; gather <compiler>, <option>, the <default> classes
// (each class holds its parents' attributes, overridden by its own) and the <asset> meshes; walk
// <worldbody>, placing each body's frame in the world from its parent's, with its geoms as shapes
// (mass from density unless an <inertial> gives it; a mesh geom collides as its convex hull and
// weighs what MuJoCo makes it weigh, io/mujoco_mesh.hpp) and its joint towards its parent; then
// <equality> constraints.
// Elements and attributes that linx does not use are counted and named in one warning.
#include <linx/bounds.hpp>
#include <linx/import.hpp>
#include <linx/mass_properties.hpp>

#include "io/import_check.hpp"
#include "io/input_file.hpp"
#include "io/mesh_file.hpp"
#include "io/mujoco_mesh.hpp"
#include "io/xml_error.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace linx {
namespace {

using tinyxml2::XMLElement;

constexpr int kMaxIncludeDepth = 16;
// Bounds on what includes may make of a small model (nine files of 1 kB, each including the next
// 16 times, would be 16^8 copies), over the whole model: the <include>s read, the bytes read, and
// the elements copied (the work of splicing).
constexpr int kMaxIncludes = 1000;
constexpr std::uint64_t kMaxModelBytes = io::kModelLimit;
constexpr std::size_t kMaxModelElements = 1'000'000;
constexpr double kDefaultDensity = 1000.0;  // MuJoCo's geom density (kg/m^3)

// Attributes of an element type ("joint", "geom") by name.
using Attributes = std::map<std::string, std::string>;

class MjcfImporter {
 public:
  MjcfImporter(const std::filesystem::path& path, const ImportOptions& options)
      : path_(path), file_(path.string()), options_(options) {}

  Scene run() {
    bytes_ = load(path_, doc_);
    XMLElement* root = doc_.FirstChildElement("mujoco");
    if (!root) fail("mujoco", "an MJCF file needs a <mujoco> element");
    spliceIncludes(root, path_, 0);
    scene_.file = file_;
    scene_.settings.timestep = 0.002;  // MuJoCo's default
    for (XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "compiler")
        compiler(e);
      else if (tag == "option")
        option(e);
      else if (tag == "default")
        defaults(e, "main", "");
      else if (tag == "asset")
        assets(e);
      else if (tag != "worldbody" && tag != "equality" && tag != "actuator")
        unused("<" + tag + ">");
    }
    for (XMLElement* w = root->FirstChildElement("worldbody"); w;
         w = w->NextSiblingElement("worldbody"))
      worldbody(w);
    for (XMLElement* q = root->FirstChildElement("equality"); q;
         q = q->NextSiblingElement("equality"))
      equality(q);
    for (XMLElement* a = root->FirstChildElement("actuator"); a;
         a = a->NextSiblingElement("actuator"))
      actuators(a);
    warn();
    io::completeImported(scene_, "body");
    return std::move(scene_);
  }

 private:
  // ---- reading ----

  // Returns the file's size.
  static std::uint64_t load(const std::filesystem::path& path, tinyxml2::XMLDocument& doc) {
    std::string text;
    try {
      text = io::readInputFile(path, io::kModelLimit, "an MJCF file");
    } catch (const std::runtime_error& e) {
      throw SceneError(path.string(), "", e.what());
    }
    io::parseXml(doc, text, path.string());
    return text.size();
  }

  static std::size_t elementsIn(const XMLElement* e) {
    std::size_t n = 1;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      n += elementsIn(c);
    return n;
  }

  // <include file="..."/>: the included file's top-level children (inside its own <mujoco>) take
  // its place, as MuJoCo does. `file`: the file that holds `parent` (messages about an <include>
  // name it, and the include's line).
  void spliceIncludes(XMLElement* parent, const std::filesystem::path& file, int depth) {
    const auto refuse = [&](const XMLElement* e, const std::string& problem) {
      throw SceneError(file.string(), where(e), problem);
    };
    for (XMLElement* e = parent->FirstChildElement(); e;) {
      XMLElement* next = e->NextSiblingElement();
      if (std::string(e->Name()) == "include") {
        if (depth >= kMaxIncludeDepth)
          refuse(e, fmt::format("more than {} nested includes", kMaxIncludeDepth));
        if (++includes_ > kMaxIncludes)
          refuse(e, fmt::format("more than {} includes read in the whole model (each <include> "
                                "counts, a file included twice twice)",
                                kMaxIncludes));
        const char* name = e->Attribute("file");
        if (!name) refuse(e, "file: missing");
        const std::filesystem::path included = file.parent_path() / name;
        std::string text;
        try {
          io::checkInsideFolder(included, path_.parent_path(), options_.allow_outside_paths);
          text = io::readInputFile(included, io::kModelLimit, "an MJCF file");
        } catch (const std::runtime_error& error) {
          refuse(e, fmt::format("file '{}': {}", name, error.what()));
        }
        bytes_ += text.size();
        if (bytes_ > kMaxModelBytes)
          refuse(e, fmt::format("file '{}': the model and the includes read reach {} bytes, above "
                                "the limit of {} for a whole model",
                                name, bytes_, kMaxModelBytes));
        tinyxml2::XMLDocument other;
        io::parseXml(other, text, included.string());
        XMLElement* other_root = other.FirstChildElement("mujoco");
        if (!other_root) throw SceneError(included.string(), "mujoco", "needs a <mujoco> element");
        spliceIncludes(other_root, included, depth + 1);
        // Counted before cloning, so that a bound passed costs nothing more.
        for (const XMLElement* c = other_root->FirstChildElement(); c; c = c->NextSiblingElement())
          spliced_ += elementsIn(c);
        if (spliced_ > kMaxModelElements)
          refuse(e, fmt::format("file '{}': the includes copy more than {} elements in all (an "
                                "element counted at each include it is copied through)",
                                name, kMaxModelElements));
        tinyxml2::XMLNode* after = e;
        for (XMLElement* c = other_root->FirstChildElement(); c; c = c->NextSiblingElement()) {
          // Into the document that holds `parent` (an included file's, for a nested include):
          // tinyxml2 inserts no node of another document, and a nested include's elements were
          // silently dropped.
          XMLElement* copy = c->DeepClone(parent->GetDocument())->ToElement();
          noteOrigins(c, copy, included);
          after = parent->InsertAfterChild(after, copy);
        }
        parent->DeleteChild(e);
      } else {
        spliceIncludes(e, file, depth);
      }
      e = next;
    }
  }

  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw SceneError(file_, where, problem);
  }

  void unused(const std::string& what) { ++unused_[what]; }

  // A joint that starts outside its range starts at its nearest bound (io::startInsideLimits).
  void startInside(CoordinateDef& c, const std::string& joint, bool angular) {
    if (auto moved = io::startInsideLimits(c, joint, angular)) started_outside_.push_back(*moved);
  }

  void warn() {
    if (!started_outside_.empty())
      scene_.warnings.push_back(
          fmt::format("{}: {}", file_, io::startOutsideWarning(started_outside_)));
    if (unused_.empty()) return;
    std::string list;
    for (const auto& [what, count] : unused_)
      list += fmt::format("{}{}{}", list.empty() ? "" : ", ", what,
                          count > 1 ? fmt::format(" (x{})", count) : "");
    scene_.warnings.insert(scene_.warnings.begin(),
                           fmt::format("{}: not used by linx, ignored: {}", file_, list));
  }

  // Where an element came from when an <include> copied it in (a copy has no line of its own):
  // its file, relative to the model's folder, and its line there.
  struct Origin {
    std::string file;
    int line = 0;
  };
  std::map<const XMLElement*, Origin> origins_;

  /// Records the origin of `copy` and its descendants, copied from `original` in `file` (or from
  /// where `original` itself was copied from; its entry goes, as it dies with its document).
  void noteOrigins(const XMLElement* original, const XMLElement* copy,
                   const std::filesystem::path& file) {
    auto known = origins_.extract(original);
    origins_[copy] = known ? known.mapped()
                           : Origin{file.lexically_relative(path_.parent_path()).string(),
                                    original->GetLineNum()};
    const XMLElement* c = copy->FirstChildElement();
    for (const XMLElement* o = original->FirstChildElement(); o && c;
         o = o->NextSiblingElement(), c = c->NextSiblingElement())
      noteOrigins(o, c, file);
  }

  /// An element for a message: its tag, its name, and its line (and file, if included).
  std::string where(const XMLElement* e) const {
    const char* name = e->Attribute("name");
    const std::string what = name ? fmt::format("{} '{}'", e->Name(), name) : e->Name();
    if (const auto it = origins_.find(e); it != origins_.end())
      return fmt::format("{} ({}, line {})", what, it->second.file, it->second.line);
    return fmt::format("{} (line {})", what, e->GetLineNum());
  }

  std::vector<double> numbers(const std::string& text, const XMLElement* e,
                              const std::string& attribute) const {
    std::istringstream in(text);
    std::vector<double> out;
    std::string word;
    while (in >> word) {
      std::size_t used = 0;
      double value = 0.0;
      try {
        value = std::stod(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || !std::isfinite(value))
        fail(where(e), fmt::format("{}: '{}' is not a finite number", attribute, word));
      out.push_back(value);
    }
    return out;
  }

  // ---- attributes, with the default classes ----

  // An element's attribute, else its class's default for its kind of element.
  std::optional<std::string> attribute(const XMLElement* e, const std::string& kind,
                                       const std::string& cls, const std::string& name) const {
    if (const char* own = e->Attribute(name.c_str())) return std::string(own);
    const auto c = defaults_.find(cls);
    if (c == defaults_.end()) return std::nullopt;
    const auto k = c->second.find(kind);
    if (k == c->second.end()) return std::nullopt;
    const auto a = k->second.find(name);
    if (a == k->second.end()) return std::nullopt;
    return a->second;
  }

  std::optional<std::vector<double>> vector(const XMLElement* e, const std::string& kind,
                                            const std::string& cls, const std::string& name,
                                            std::size_t size) const {
    const auto text = attribute(e, kind, cls, name);
    if (!text) return std::nullopt;
    std::vector<double> v = numbers(*text, e, name);
    if (size && v.size() != size)
      fail(where(e), fmt::format("{}: needs {} numbers, got {}", name, size, v.size()));
    return v;
  }

  double number(const XMLElement* e, const std::string& kind, const std::string& cls,
                const std::string& name, double otherwise) const {
    const auto v = vector(e, kind, cls, name, 1);
    return v ? (*v)[0] : otherwise;
  }

  // The class an element takes: its own, else the nearest childclass of its bodies, else main.
  // A class that names no default is refused, as MuJoCo refuses it.
  std::string classOf(const XMLElement* e, const std::string& childclass) const {
    const char* own = e->Attribute("class");
    if (own && !defaults_.count(own))
      fail(where(e), fmt::format("class: no default class '{}'", own));
    return own ? own : childclass;
  }

  void defaults(XMLElement* d, const std::string& name, const std::string& parent) {
    if (defaults_.count(name) && name != "main")
      fail(where(d), "a default class of that name exists");
    defaults_[name] = parent.empty() ? std::map<std::string, Attributes>{} : defaults_[parent];
    for (XMLElement* e = d->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string kind = e->Name();
      if (kind == "default") {
        const char* child = e->Attribute("class");
        if (!child) fail(where(e), "a nested default needs a class");
        defaults(e, child, name);
        continue;
      }
      for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
        defaults_[name][kind][a->Name()] = a->Value();
    }
  }

  // ---- top-level settings ----

  void compiler(const XMLElement* e) {
    if (const char* angle = e->Attribute("angle")) {
      const std::string a = angle;
      if (a != "degree" && a != "radian") fail(where(e), "angle: must be degree or radian");
      degrees_ = a == "degree";
    }
    if (const char* seq = e->Attribute("eulerseq")) {
      euler_sequence_ = seq;
      const bool ok = euler_sequence_.size() == 3 &&
                      std::all_of(euler_sequence_.begin(), euler_sequence_.end(), [](char c) {
                        return std::string("xyzXYZ").find(c) != std::string::npos;
                      });
      if (!ok) fail(where(e), "eulerseq: three of x, y, z, X, Y, Z");
    }
    // Mesh files: in meshdir (else assetdir) under the model's folder, as MuJoCo finds them.
    if (const char* dir = e->Attribute("assetdir"); dir && mesh_folder_.empty()) mesh_folder_ = dir;
    if (const char* dir = e->Attribute("meshdir")) mesh_folder_ = dir;
    if (const char* strip = e->Attribute("strippath")) strip_paths_ = flag(e, "strippath", strip);
    if (const char* exact = e->Attribute("exactmeshinertia"))
      exact_mesh_inertia_ = flag(e, "exactmeshinertia", exact);
    if (const char* from = e->Attribute("inertiafromgeom")) {
      inertia_from_geom_ = from;
      if (inertia_from_geom_ != "auto" && inertia_from_geom_ != "true" &&
          inertia_from_geom_ != "false")
        fail(where(e), "inertiafromgeom: must be true, false or auto");
    }
    if (const auto groups = vector(e, "", "", "inertiagrouprange", 2))
      inertia_groups_ = {(*groups)[0], (*groups)[1]};
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      const std::string n = a->Name();
      if (n != "angle" && n != "eulerseq" && n != "inertiafromgeom" && n != "autolimits" &&
          n != "meshdir" && n != "assetdir" && n != "strippath" && n != "exactmeshinertia" &&
          n != "inertiagrouprange" && n != "convexhull" && n != "texturedir")
        unused(fmt::format("<compiler {}>", n));
    }
  }

  bool flag(const XMLElement* e, const char* name, const std::string& value) const {
    if (value != "true" && value != "false")
      fail(where(e), fmt::format("{}: must be true or false, got '{}'", name, value));
    return value == "true";
  }

  void option(const XMLElement* e) {
    if (e->Attribute("timestep")) {
      const double timestep = number(e, "", "", "timestep", 0.0);
      if (!(timestep > 0.0))
        fail(where(e), fmt::format("timestep: must be > 0, got {}", e->Attribute("timestep")));
      if (timestep < kMinTimestep)
        fail(where(e), fmt::format("timestep: {} s is below {:g} s, the shortest step whose square "
                                   "(the step forms h^2) is a normal double",
                                   e->Attribute("timestep"), kMinTimestep));
      scene_.settings.timestep = timestep;
    }
    if (const auto g = vector(e, "", "", "gravity", 3))
      scene_.settings.gravity = {(*g)[0], (*g)[1], (*g)[2]};
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      const std::string n = a->Name();
      if (n != "timestep" && n != "gravity") unused(fmt::format("<option {}>", n));
    }
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      unused(fmt::format("<option><{}>", c->Name()));
  }

  // <asset>: meshes, read when a geom uses them (after <compiler>, which may come later and says
  // where their files are). Textures and materials only colour MuJoCo's pictures.
  void assets(const XMLElement* e) {
    for (const XMLElement* a = e->FirstChildElement(); a; a = a->NextSiblingElement()) {
      if (std::string(a->Name()) != "mesh") {
        unused(fmt::format("<asset><{}>", a->Name()));
        continue;
      }
      const char* file = a->Attribute("file");
      if (!file) fail(where(a), "file: missing (meshes given by vertex and face are not read)");
      // Unnamed, a mesh takes its file's name without folder and extension, as in MuJoCo.
      const std::string name =
          a->Attribute("name") ? a->Attribute("name") : std::filesystem::path(file).stem().string();
      if (!mesh_assets_.emplace(name, a).second)
        fail(where(a), fmt::format("a second mesh named '{}'", name));
    }
  }

  // A mesh asset, read and weighed once.
  struct Mesh {
    std::vector<Vec3> points;  // the vertices as MuJoCo holds them (scaled, single precision)
    io::MeshMass mass;         // per unit density
  };

  const Mesh& mesh(const XMLElement* geom, const std::string& name) {
    if (const auto found = meshes_.find(name); found != meshes_.end()) return found->second;
    const auto asset = mesh_assets_.find(name);
    if (asset == mesh_assets_.end()) fail(where(geom), fmt::format("mesh: no mesh '{}'", name));
    const XMLElement* e = asset->second;
    const std::string cls = classOf(e, "main");
    std::filesystem::path file = e->Attribute("file");
    if (strip_paths_) file = file.filename();
    const std::filesystem::path path = path_.parent_path() / mesh_folder_ / file;
    ShapeDef read;
    try {
      io::checkInsideFolder(path, path_.parent_path(), options_.allow_outside_paths);
      read = io::loadMeshFile(path.string(), io::ObjPolygons::Fanned);
    } catch (const std::runtime_error& error) {
      fail(where(e), error.what());  // names the file as found
    }
    const auto three = [&](const char* attr, Vec3 otherwise) {
      const auto v = vector(e, "mesh", cls, attr, 3);
      return v ? Vec3((*v)[0], (*v)[1], (*v)[2]) : otherwise;
    };
    const Vec3 scale = three("scale", Vec3::Ones());
    if (!(scale.cwiseAbs().minCoeff() > 0.0)) fail(where(e), "scale: must not be zero");
    const auto q = vector(e, "mesh", cls, "refquat", 4);
    const Quat refquat = q ? Quat((*q)[0], (*q)[1], (*q)[2], (*q)[3]) : Quat::Identity();
    if (!(refquat.norm() > 0.0)) fail(where(e), "refquat: must not be zero");
    const io::MujocoMesh held = io::mujocoMesh(read, scale, three("refpos", Vec3::Zero()), refquat);
    Mesh out;
    try {
      out.mass = io::mujocoMeshMass(held, exact_mesh_inertia_);
    } catch (const std::exception& error) {
      fail(where(e),
           fmt::format("file '{}': {} (MuJoCo refuses it too)", file.string(), error.what()));
    }
    for (const auto& v : held.vertices) out.points.emplace_back(v[0], v[1], v[2]);
    return meshes_.emplace(name, std::move(out)).first->second;
  }

  // ---- frames ----

  double angle(double value) const { return degrees_ ? value * std::numbers::pi / 180.0 : value; }

  // An element's orientation from whichever of quat, axisangle, euler, xyaxes, zaxis it has.
  Quat orientation(const XMLElement* e) const {
    if (const auto q = vector(e, "", "", "quat", 4)) {
      const Quat out((*q)[0], (*q)[1], (*q)[2], (*q)[3]);
      if (!(out.norm() > 0)) fail(where(e), "quat: must not be zero");
      return out.normalized();
    }
    if (const auto a = vector(e, "", "", "axisangle", 4)) {
      const Vec3 axis((*a)[0], (*a)[1], (*a)[2]);
      if (!(axis.norm() > 0)) fail(where(e), "axisangle: the axis must not be zero");
      return Quat(Eigen::AngleAxisd(angle((*a)[3]), axis.normalized()));
    }
    if (const auto r = vector(e, "", "", "euler", 3)) {
      Quat q = Quat::Identity();
      for (int i = 0; i < 3; ++i) {
        const char c = euler_sequence_[static_cast<std::size_t>(i)];
        const auto lower = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const Vec3 axis = Vec3::Unit(static_cast<Eigen::Index>(std::string("xyz").find(lower)));
        const Quat turn(Eigen::AngleAxisd(angle((*r)[static_cast<std::size_t>(i)]), axis));
        q = lower == c ? q * turn : turn * q;  // lowercase: axes that turn with the frame
      }
      return q.normalized();
    }
    if (const auto xy = vector(e, "", "", "xyaxes", 6)) {
      const Vec3 x = Vec3((*xy)[0], (*xy)[1], (*xy)[2]).normalized();
      Vec3 y((*xy)[3], (*xy)[4], (*xy)[5]);
      y = (y - y.dot(x) * x).normalized();
      Mat3 r;
      r << x, y, x.cross(y);
      if (!r.allFinite()) fail(where(e), "xyaxes: two independent directions");
      return Quat(r).normalized();
    }
    if (const auto z = vector(e, "", "", "zaxis", 3)) {
      const Vec3 axis((*z)[0], (*z)[1], (*z)[2]);
      if (!(axis.norm() > 0)) fail(where(e), "zaxis: must not be zero");
      return Quat::FromTwoVectors(Vec3::UnitZ(), axis.normalized());
    }
    return Quat::Identity();
  }

  Pose localPose(const XMLElement* e) const {
    const auto p = vector(e, "", "", "pos", 3);
    return {p ? Vec3((*p)[0], (*p)[1], (*p)[2]) : Vec3::Zero(), orientation(e)};
  }

  static Pose compose(const Pose& a, const Pose& b) {
    return {a.toWorld(b.position), (a.orientation * b.orientation).normalized()};
  }

  // ---- bodies ----

  void worldbody(XMLElement* w) {
    for (XMLElement* e = w->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "body")
        body(e, Pose{}, -1, /*parent_moves=*/false, "main");
      else if (tag == "geom")
        worldGeom(e, "main");
      else
        unused("<" + tag + ">");
    }
  }

  // Geoms on the world: shapes of one static body, "world_geoms" ("world" names the frame).
  void worldGeom(const XMLElement* e, const std::string& cls) {
    if (world_geoms_ < 0) {
      BodyDef def;
      def.name = "world_geoms";
      def.is_static = true;
      scene_.bodies.push_back(def);
      world_geoms_ = static_cast<int>(scene_.bodies.size()) - 1;
    }
    const std::string geom_class = classOf(e, cls);
    Geom g = geom(e, geom_class, /*on_static=*/true);
    if (!g.shape) return;
    place(*g.shape, Pose{}, geomPose(e, geom_class));
    scene_.bodies[static_cast<std::size_t>(world_geoms_)].shapes.push_back(std::move(*g.shape));
  }

  void body(XMLElement* e, const Pose& parent_frame, int parent, bool parent_moves,
            const std::string& parent_class) {
    const char* name_attr = e->Attribute("name");
    const std::string name = name_attr ? name_attr : fmt::format("body{}", scene_.bodies.size());
    const char* childclass = e->Attribute("childclass");
    const std::string cls = childclass ? childclass : parent_class;
    if (childclass && !defaults_.count(cls))
      fail(where(e), fmt::format("no default class '{}'", cls));
    const Pose frame = compose(parent_frame, localPose(e));

    std::vector<XMLElement*> joints;
    bool free = false;
    for (XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "freejoint")
        free = true;
      else if (tag == "joint") {
        const std::string type = attribute(c, "joint", classOf(c, cls), "type").value_or("hinge");
        if (type == "free")
          free = true;
        else
          joints.push_back(c);
      }
    }
    if (free && !joints.empty()) fail(where(e), "a free joint and other joints in one body");
    if (free && parent >= 0)  // as MuJoCo: a free body's pose is its own, not its parent's
      fail(where(e), fmt::format("a free joint only in a body of <worldbody>, not inside body '{}' "
                                 "(as in MuJoCo)",
                                 scene_.bodies[static_cast<std::size_t>(parent)].name));
    if (joints.size() > static_cast<std::size_t>(kMaxCoordinates))
      fail(where(e),
           fmt::format("has {} joints: at most {} in one body", joints.size(), kMaxCoordinates));
    const bool moves = free || !joints.empty() || parent_moves;

    BodyDef def;
    def.name = name;
    def.is_static = !moves;
    Pose carrier = frame;  // the frame the shapes are placed in
    const XMLElement* inertial = e->FirstChildElement("inertial");
    if (inertial && inertia_from_geom_ == "true") unused("<inertial> (inertiafromgeom is true)");
    const bool given = inertial && moves && inertia_from_geom_ != "true";
    if (moves && !inertial && inertia_from_geom_ == "false")
      fail(where(e), "a moving body needs an <inertial> (the compiler's inertiafromgeom is false)");
    if (given) {
      carrier = compose(frame, localPose(inertial));
      const double mass = number(inertial, "", "", "mass", 0.0);
      def.mass = mass;
      if (const auto d = vector(inertial, "", "", "diaginertia", 3)) {
        def.inertia = Vec3((*d)[0], (*d)[1], (*d)[2]).asDiagonal();
      } else if (const auto f = vector(inertial, "", "", "fullinertia", 6)) {
        Mat3 i;
        i << (*f)[0], (*f)[3], (*f)[4], (*f)[3], (*f)[1], (*f)[5], (*f)[4], (*f)[5], (*f)[2];
        def.inertia = i;
      } else {
        fail(where(inertial), "needs diaginertia or fullinertia");
      }
    }
    // A body with mesh geoms is weighed here, as MuJoCo weighs it; others by their shapes'
    // densities (the scene keeps them, and a changed size changes the mass).
    const bool infer = moves && !given;
    const bool weighed_here = infer && hasMeshGeom(e, cls);
    std::vector<MassProperties> parts;
    std::vector<std::pair<ShapeDef, Pose>> shapes;  // each with its pose in the body's frame
    for (XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "geom") {
        const std::string geom_class = classOf(c, cls);
        const Pose local = geomPose(c, geom_class);
        Geom g = geom(c, geom_class, def.is_static);
        const bool weighs = infer && inMassGroups(c, geom_class);
        if (weighed_here && weighs) parts.push_back(geomMass(c, geom_class, g, local));
        if (!g.shape) continue;
        if (infer && !weighed_here && isSolid(g.shape->type))
          g.shape->density = weighs ? density(c, geom_class, shapeVolume(*g.shape)) : 0.0;
        shapes.emplace_back(std::move(*g.shape), local);
      } else if (tag != "body" && tag != "joint" && tag != "freejoint" && tag != "inertial") {
        unused("<" + tag + ">");
      }
    }
    if (weighed_here) {
      const MassProperties total = combine(parts);
      if (!(total.mass > 0.0))
        fail(where(e), "its geoms weigh nothing: a moving body needs a mass");
      def.mass = total.mass;
      def.inertia = total.inertia;
      carrier = Pose{frame.toWorld(total.center), frame.orientation};
    }
    def.position = carrier.position;
    def.orientation = carrier.orientation;
    for (auto& [shape, local] : shapes) {
      place(shape, carrier, compose(frame, local));
      def.shapes.push_back(std::move(shape));
    }
    if (infer && !weighed_here && def.shapes.empty())
      fail(where(e), "a moving body needs an <inertial> or geoms to give it a mass");
    scene_.bodies.push_back(std::move(def));
    const int index = static_cast<int>(scene_.bodies.size()) - 1;
    body_index_[name] = index;
    body_frame_[name] = frame;

    if (joints.size() == 1)
      joint(joints[0], classOf(joints[0], cls), frame, index, parent);
    else if (joints.size() > 1)
      serialJoint(joints, cls, frame, index, parent);
    else if (!free && parent_moves)
      weld(name, frame.position, index, parent);

    for (XMLElement* c = e->FirstChildElement("body"); c; c = c->NextSiblingElement("body"))
      body(c, frame, index, moves, cls);
  }

  void weld(const std::string& name, const Vec3& at, int body1, int body2) {
    SceneJoint j;
    j.type = "fixed";
    j.def.name = name + "_weld";
    j.def.body1 = BodyId{body1};
    j.def.body2 = BodyId{body2};
    j.def.anchor = at;
    scene_.joints.push_back(std::move(j));
  }

  // A <joint>'s name, or its body's (and its place there, when the body has several).
  std::string jointName(const XMLElement* e, int body,
                        std::optional<std::size_t> place = {}) const {
    if (e->Attribute("name")) return e->Attribute("name");
    const std::string& name = scene_.bodies[static_cast<std::size_t>(body)].name;
    return place ? fmt::format("{}_joint{}", name, *place) : name + "_joint";
  }

  // A <joint>'s anchor (pos) and unit axis in the world.
  std::pair<Vec3, Vec3> jointAxis(const XMLElement* e, const std::string& cls,
                                  const Pose& frame) const {
    const auto pos = vector(e, "joint", cls, "pos", 3);
    const Vec3 anchor = frame.toWorld(pos ? Vec3((*pos)[0], (*pos)[1], (*pos)[2]) : Vec3::Zero());
    const auto axis = vector(e, "joint", cls, "axis", 3);
    const Vec3 a = axis ? Vec3((*axis)[0], (*axis)[1], (*axis)[2]) : Vec3::UnitZ();
    if (!(a.norm() > 0)) fail(where(e), "axis: must not be zero");
    return {anchor, frame.orientation * a.normalized()};
  }

  void joint(const XMLElement* e, const std::string& cls, const Pose& frame, int body1, int body2) {
    const std::string type = attribute(e, "joint", cls, "type").value_or("hinge");
    SceneJoint j;
    JointDef& def = j.def;
    def.name = jointName(e, body1);
    def.body1 = BodyId{body1};
    def.body2 = BodyId{body2};
    std::tie(def.anchor, def.axis) = jointAxis(e, cls, frame);
    if (type == "hinge")
      j.type = "hinge";
    else if (type == "slide")
      j.type = "slider";
    else if (type == "ball")
      j.type = "ball";
    else
      fail(where(e), fmt::format("type: '{}' is not a joint type linx reads", type));
    def.coordinates[0] = coordinate(e, cls, type);
    startInside(def.coordinates[0], def.name, type != "slide");
    joint_coordinate_[def.name] = {scene_.joints.size(), 0};
    scene_.joints.push_back(std::move(j));
  }

  // Several <joint>s in one body: one serial joint of their hinges and slides, in their order,
  // named after them ("a+b").
  void serialJoint(const std::vector<XMLElement*>& joints, const std::string& body_class,
                   const Pose& frame, int body1, int body2) {
    SceneJoint j;
    j.type = "serial";
    JointDef& def = j.def;
    def.body1 = BodyId{body1};
    def.body2 = BodyId{body2};
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const XMLElement* e = joints[i];
      const std::string cls = classOf(e, body_class);
      const std::string type = attribute(e, "joint", cls, "type").value_or("hinge");
      if (type != "hinge" && type != "slide")
        fail(where(e), fmt::format("type: a {} joint with other joints in one body (linx takes "
                                   "hinges and slides there)",
                                   type));
      const auto [anchor, axis] = jointAxis(e, cls, frame);
      def.axes.push_back(SerialAxis{type == "slide", axis, anchor});
      def.coordinates[i] = coordinate(e, cls, type);
      const std::string name = jointName(e, body1, i);
      startInside(def.coordinates[i], name, type != "slide");
      def.name += (i == 0 ? "" : "+") + name;
      joint_coordinate_[name] = {scene_.joints.size(), static_cast<int>(i)};
    }
    def.anchor = def.axes[0].anchor;
    scene_.joints.push_back(std::move(j));
  }

  // What acts on a <joint>'s coordinate: range, ref, stiffness and damping (a spring about
  // springref), frictionloss, armature.
  CoordinateDef coordinate(const XMLElement* e, const std::string& cls, const std::string& type) {
    CoordinateDef c;
    const bool angular = type == "hinge" || type == "ball";
    const auto scale = [&](double v) { return angular ? angle(v) : v; };
    const auto range = vector(e, "joint", cls, "range", 2);
    const std::string limited = attribute(e, "joint", cls, "limited").value_or("auto");
    if (limited != "true" && limited != "false" && limited != "auto")
      fail(where(e), "limited: must be true, false or auto");
    const bool has_limits = limited == "true" || (limited == "auto" && range);
    if (limited == "true" && !range) fail(where(e), "limited needs a range");

    if (has_limits && type != "ball") {
      if (!((*range)[0] <= (*range)[1])) fail(where(e), "range: the lower end is above the upper");
      c.limits = JointLimits{scale((*range)[0]), scale((*range)[1])};
    }
    // A ball joint's range bounds its rotation angle (only its second number counts); a bound of
    // half a turn or more never binds.
    std::optional<JointLimits> ball_limit;
    if (has_limits && type == "ball" && scale((*range)[1]) < M_PI) {
      if (!((*range)[1] >= 0)) fail(where(e), "range: a ball joint's upper end must be >= 0");
      ball_limit = JointLimits{0.0, scale((*range)[1])};
    }
    c.reference = scale(number(e, "joint", cls, "ref", 0.0));
    const double stiffness = number(e, "joint", cls, "stiffness", 0.0);
    const double damping = number(e, "joint", cls, "damping", 0.0);
    if (stiffness < 0 || damping < 0) fail(where(e), "stiffness and damping must be >= 0");
    if ((stiffness > 0 || damping > 0) && type != "ball")
      c.spring = JointSpring{stiffness, damping, scale(number(e, "joint", cls, "springref", 0.0))};
    else if (stiffness > 0 || damping > 0)
      unused("ball joint stiffness and damping");
    const double friction = number(e, "joint", cls, "frictionloss", 0.0);
    if (friction < 0) fail(where(e), "frictionloss must be >= 0");
    if (type != "ball")
      c.friction = friction;
    else if (friction > 0)
      unused("ball joint frictionloss");
    for (const char* a :
         {"solreflimit", "solimplimit", "solreffriction", "solimpfriction", "margin"})
      if (attribute(e, "joint", cls, a)) unused(fmt::format("joint {}", a));
    const double armature = number(e, "joint", cls, "armature", 0.0);
    if (armature < 0) fail(where(e), "armature must be >= 0");
    if (type != "ball") c.armature = armature;
    if (type == "ball") {
      if (armature > 0) unused("ball joint armature");
      c = CoordinateDef{.limits = ball_limit};
    }
    return c;
  }

  // ---- actuators: each on one joint's coordinate, at zero control (MuJoCo's start) ----

  void actuators(const XMLElement* list) {
    static const std::set<std::string> kinds{"general", "motor", "position", "velocity", "damper"};
    for (const XMLElement* e = list->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string kind = e->Name();
      if (!kinds.count(kind)) {
        unused("<actuator><" + kind + ">");
        continue;
      }
      const char* joint = e->Attribute("joint");
      if (!joint) {  // tendon, site, body transmissions
        unused("<actuator><" + kind + "> without a joint");
        continue;
      }
      const auto found = joint_coordinate_.find(joint);
      if (found == joint_coordinate_.end())
        fail(where(e), fmt::format("joint: no hinge or slide joint named '{}'", joint));
      const std::string cls = classOf(e, "main");
      if (attribute(e, kind, cls, "dyntype").value_or("none") != "none") {
        unused("<actuator><" + kind + "> with activation (dyntype)");
        continue;
      }
      SceneJoint& j = scene_.joints[found->second.first];
      CoordinateDef& c = j.def.coordinates[static_cast<std::size_t>(found->second.second)];
      actuator(e, kind, cls, c);
    }
  }

  // An actuator's force is MuJoCo's gain times its control plus its bias, each affine in the
  // actuator's length L and velocity L' (gainprm and biasprm: p0 + p1 L + p2 L'). The shortcuts
  // are generals of fixed forms: a motor gain 1; a position servo gain kp, bias -kp L - kv L'; a
  // velocity servo gain kv, bias -kv L'; a damper gain -kv L'.
  struct Affine {
    double constant = 0.0, length = 0.0, velocity = 0.0;
  };

  std::pair<Affine, Affine> gainAndBias(const XMLElement* e, const std::string& kind,
                                        const std::string& cls) const {
    const auto positive = [&](const char* name, double otherwise, bool zero_allowed) {
      const double v = number(e, kind, cls, name, otherwise);
      if (zero_allowed ? !(v >= 0.0) : !(v > 0.0))
        fail(where(e), fmt::format("{}: must be {} 0", name, zero_allowed ? ">=" : ">"));
      return v;
    };
    if (kind == "motor") return {{1.0, 0.0, 0.0}, {}};
    if (kind == "position") {
      const double kp = positive("kp", 1.0, false), kv = positive("kv", 0.0, true);
      return {{kp, 0.0, 0.0}, {0.0, -kp, -kv}};
    }
    if (kind == "velocity") {
      const double kv = positive("kv", 1.0, false);
      return {{kv, 0.0, 0.0}, {0.0, 0.0, -kv}};
    }
    if (kind == "damper") return {{0.0, 0.0, -positive("kv", 1.0, true)}, {}};
    const auto parameters = [&](const char* name, const char* type_name, const char* otherwise) {
      const std::string type = attribute(e, kind, cls, type_name).value_or(otherwise);
      if (type != "fixed" && type != "affine" && type != "none")
        fail(where(e),
             fmt::format("{}: '{}' is not read (fixed, affine or none)", type_name, type));
      const std::vector<double> p = vector(e, kind, cls, name, 0).value_or(std::vector<double>{});
      const auto at = [&](std::size_t i, double d) { return i < p.size() ? p[i] : d; };
      if (type == "none") return Affine{};
      if (type == "fixed") return Affine{at(0, 1.0), 0.0, 0.0};
      return Affine{at(0, 1.0), at(1, 0.0), at(2, 0.0)};
    };
    Affine gain = parameters("gainprm", "gaintype", "fixed");
    Affine bias = parameters("biasprm", "biastype", "none");
    if (attribute(e, kind, cls, "biastype").value_or("none") == "affine" &&
        !vector(e, kind, cls, "biasprm", 0))
      bias = Affine{};  // MuJoCo's biasprm defaults to zeros
    return {gain, bias};
  }

  // MuJoCo's actuator on a joint of coordinate q, with gear g and control u (0 until a controller
  // sets it, clamped to ctrlrange): its length is L = g q and its force F acts on q as g F. At a
  // fixed control, F = c0 + c1 L + c2 L' (gain times u plus bias): with c1 < 0 a servo of
  // stiffness -c1 g^2 and damping -c2 g^2 towards q = -c0 / (c1 g); with c1 = 0 and c2 < 0 a
  // damped motor towards q' = -c0 / (c2 g); with both 0 a constant force g c0 (CoordinateDef::
  // force). forcerange bounds F: the servo's max_force is g times it.
  void actuator(const XMLElement* e, const std::string& kind, const std::string& cls,
                CoordinateDef& c) {
    const auto gear = vector(e, kind, cls, "gear", 0);
    const double g = gear && !gear->empty() ? (*gear)[0] : 1.0;
    if (gear && gear->size() > 1 &&
        std::any_of(gear->begin() + 1, gear->end(), [](double v) { return v != 0.0; }))
      unused("actuator gear beyond its first number");
    if (!(g != 0.0)) fail(where(e), "gear: must not be zero");
    double control = 0.0;
    const std::string ctrllimited = attribute(e, kind, cls, "ctrllimited").value_or("auto");
    const auto ctrlrange = vector(e, kind, cls, "ctrlrange", 2);
    if (ctrlrange && ctrllimited != "false")
      control = std::clamp(control, (*ctrlrange)[0], std::max((*ctrlrange)[0], (*ctrlrange)[1]));
    double max_force = kInfinity, low = -kInfinity, high = kInfinity;
    const std::string forcelimited = attribute(e, kind, cls, "forcelimited").value_or("auto");
    if (const auto range = vector(e, kind, cls, "forcerange", 2);
        range && forcelimited != "false") {
      if (!((*range)[0] <= 0.0 && (*range)[1] >= 0.0))
        fail(where(e), "forcerange: must contain zero");
      if ((*range)[0] != -(*range)[1]) unused("asymmetric actuator forcerange (the larger bound)");
      max_force = std::abs(g) * std::max(-(*range)[0], (*range)[1]);
      low = (*range)[0];
      high = (*range)[1];
    }
    const auto [gain, bias] = gainAndBias(e, kind, cls);
    const double c0 = gain.constant * control + bias.constant;
    const double c1 = gain.length * control + bias.length;
    const double c2 = gain.velocity * control + bias.velocity;
    if (c1 > 0.0 || c2 > 0.0)
      fail(where(e),
           "pushes away from where it is (a gain or bias growing with the actuator's "
           "length or velocity): not read");
    if (c1 == 0.0 && c2 == 0.0) {
      const double force = g * std::clamp(c0, low, high);
      c.force = Signal(c.force ? c.force->at(0.0) + force : force);
      return;
    }
    if (c.motor) fail(where(e), "a second servo or damped actuator on one joint");
    JointMotor m;
    m.max_force = max_force;
    m.damping = -c2 * g * g;
    if (c1 < 0.0) {
      m.stiffness = -c1 * g * g;
      m.target_position = Signal(-c0 / (c1 * g));
    } else {
      m.target_velocity = Signal(-c0 / (c2 * g));
    }
    c.motor = m;
  }

  // fromto's segment: its middle and direction as a frame (z along it), and its length.
  std::pair<Pose, double> fromTo(const std::vector<double>& f, const XMLElement* e) const {
    const Vec3 from(f[0], f[1], f[2]), to(f[3], f[4], f[5]);
    if (!((to - from).norm() > 0)) fail(where(e), "fromto: the two ends must differ");
    return {Pose{0.5 * (from + to), Quat::FromTwoVectors(Vec3::UnitZ(), (to - from).normalized())},
            (to - from).norm()};
  }

  // Where a geom is in its body's frame: by fromto, or pos and an orientation.
  Pose geomPose(const XMLElement* e, const std::string& cls) const {
    if (const auto f = vector(e, "geom", cls, "fromto", 6)) return fromTo(*f, e).first;
    return localPose(e);
  }

  // Places a shape at `world` relative to the frame of the body carrying it.
  static void place(ShapeDef& s, const Pose& carrier, const Pose& world) {
    s.position = carrier.toLocal(world.position);
    s.orientation = (carrier.orientation.conjugate() * world.orientation).normalized();
  }

  // A geom: its shape (placed by the caller, without a density), and its mesh if it is a mesh
  // geom. A mesh geom that collides with nothing (contype and conaffinity 0: a visual mesh) has no
  // shape; it still weighs, as in MuJoCo.
  struct Geom {
    std::optional<ShapeDef> shape;
    const Mesh* mesh = nullptr;
  };

  bool hasMeshGeom(const XMLElement* body, const std::string& cls) const {
    for (const XMLElement* c = body->FirstChildElement("geom"); c;
         c = c->NextSiblingElement("geom"))
      if (attribute(c, "geom", classOf(c, cls), "type") == "mesh") return true;
    return false;
  }

  // Whether a geom weighs: its group in the compiler's inertiagrouprange (all groups by default).
  bool inMassGroups(const XMLElement* e, const std::string& cls) const {
    const double group = number(e, "geom", cls, "group", 0.0);
    return group >= inertia_groups_[0] && group <= inertia_groups_[1];
  }

  // A geom's density: its mass over `volume` (MuJoCo's volume for its mass), else its density.
  double density(const XMLElement* e, const std::string& cls, double volume) const {
    if (const auto mass = vector(e, "geom", cls, "mass", 1)) {
      if (!((*mass)[0] >= 0.0))
        fail(where(e), fmt::format("mass: must be >= 0, got {}", (*mass)[0]));
      return (*mass)[0] == 0.0 ? 0.0 : (*mass)[0] / volume;
    }
    const double d = number(e, "geom", cls, "density", kDefaultDensity);
    if (!(d >= 0.0)) fail(where(e), fmt::format("density: must be >= 0, got {}", d));
    return d;
  }

  // A geom's mass, centre and inertia in its body's frame (`local`: the geom's pose there).
  MassProperties geomMass(const XMLElement* e, const std::string& cls, const Geom& g,
                          const Pose& local) const {
    if (!g.mesh) {
      ShapeDef s = *g.shape;
      s.position = local.position;
      s.orientation = local.orientation;
      return shapeMassProperties(s, density(e, cls, shapeVolume(s)));
    }
    const io::MeshMass& m = g.mesh->mass;
    const double rho = density(e, cls, m.volume);
    const Mat3 r = local.orientation.toRotationMatrix();
    return {rho * m.volume, local.toWorld(m.centre), rho * (r * m.inertia * r.transpose())};
  }

  Geom geom(const XMLElement* e, const std::string& cls, bool on_static) {
    Geom g;
    ShapeDef s;
    const std::string type = attribute(e, "geom", cls, "type").value_or("sphere");
    if (type != "mesh" && attribute(e, "geom", cls, "mesh"))
      fail(where(e), fmt::format("mesh: a {} fitted to a mesh is not read (type 'mesh' is)", type));
    const std::vector<double> size =
        vector(e, "geom", cls, "size", 0).value_or(std::vector<double>{});
    const auto need = [&](std::size_t n) {  // the first n numbers, each > 0
      if (size.size() < n)
        fail(where(e), fmt::format("size: {} {} needs {} numbers",
                                   type.find_first_of("aeiou") == 0 ? "an" : "a", type, n));
      for (std::size_t i = 0; i < n; ++i)
        if (!(size[i] > 0.0))
          fail(where(e), fmt::format("size: the {} must be > 0, got {}",
                                     n == 1   ? "radius"
                                     : n == 2 ? "radius and half-length"
                                              : "3 half-sizes",
                                     *attribute(e, "geom", cls, "size")));
    };
    const auto fromto = vector(e, "geom", cls, "fromto", 6);
    double half_length = 0.0;
    if (type == "sphere") {
      need(1);
      s.type = ShapeType::Sphere;
      s.radius = size[0];
    } else if (type == "capsule" || type == "cylinder") {
      s.type = type == "capsule" ? ShapeType::Capsule : ShapeType::Cylinder;
      need(fromto ? 1 : 2);
      s.radius = size[0];
      half_length = fromto ? 0.0 : size[1];
    } else if (type == "box") {
      need(3);
      s.type = ShapeType::Box;
      s.size = 2.0 * Vec3(size[0], size[1], size[2]);
    } else if (type == "ellipsoid") {
      need(3);
      s.type = ShapeType::Ellipsoid;
      s.radii = Vec3(size[0], size[1], size[2]);
    } else if (type == "mesh") {
      const auto name = attribute(e, "geom", cls, "mesh");
      if (!name) fail(where(e), "mesh: a mesh geom needs one");
      g.mesh = &mesh(e, *name);
      s.type = ShapeType::Convex;  // MuJoCo collides a mesh as its convex hull
      s.points = g.mesh->points;
    } else if (type == "plane") {
      if (!on_static) fail(where(e), "a plane geom must be on the world or a static body");
      s.type = ShapeType::Plane;
      s.normal = Vec3::UnitZ();
      s.offset = 0.0;
    } else {
      fail(where(e), fmt::format("type: '{}' is not a geom type linx reads (sphere, capsule, "
                                 "cylinder, box, ellipsoid, mesh, plane)",
                                 type));
    }
    if (fromto) {
      if (s.type != ShapeType::Capsule && s.type != ShapeType::Cylinder)
        fail(where(e), "fromto: only on capsules and cylinders here");
      half_length = 0.5 * (fromTo(*fromto, e).second);
    }
    if (s.type == ShapeType::Capsule || s.type == ShapeType::Cylinder) s.length = 2.0 * half_length;
    const auto friction = vector(e, "geom", cls, "friction", 0);
    if (friction && !friction->empty()) s.friction = (*friction)[0];
    if (friction && friction->size() > 1) unused("geom friction's torsional and rolling parts");
    // Contact softness and dimensionality: linx's contacts are its own (docs/model-import.md).
    for (const char* a : {"condim", "solref", "solimp", "solmix", "margin", "gap", "priority"})
      if (attribute(e, "geom", cls, a)) unused(fmt::format("geom {}", a));
    s.group = bits(e, cls, "contype");
    s.mask = bits(e, cls, "conaffinity");
    if (g.mesh && s.group == 0 && s.mask == 0) {
      unused("visual mesh geoms (contype and conaffinity 0: weighed, not drawn)");
      return g;
    }
    g.shape = std::move(s);
    return g;
  }

  // contype and conaffinity: 32 bits, written as a whole number (default 1).
  std::uint32_t bits(const XMLElement* e, const std::string& cls, const char* name) const {
    const double v = number(e, "geom", cls, name, 1.0);
    if (!(v >= 0.0 && v <= 4294967295.0 && v == std::floor(v)))
      fail(where(e), fmt::format("{}: must be a whole number in [0, 4294967295], got {}", name,
                                 *attribute(e, "geom", cls, name)));
    return static_cast<std::uint32_t>(v);
  }

  void equality(const XMLElement* q) {
    for (const XMLElement* e = q->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag != "connect" && tag != "weld") {
        unused("<equality><" + tag + ">");
        continue;
      }
      if (const char* active = e->Attribute("active"); active && std::string(active) == "false")
        continue;
      const auto body = [&](const char* attribute_name, bool required) {
        const char* n = e->Attribute(attribute_name);
        if (!n || std::string(n) == "world") {
          if (required) fail(where(e), fmt::format("needs {}", attribute_name));
          return -1;
        }
        const auto it = body_index_.find(n);
        if (it == body_index_.end())
          fail(where(e), fmt::format("{}: no body '{}'", attribute_name, n));
        return it->second;
      };
      SceneJoint j;
      j.def.name = e->Attribute("name") ? e->Attribute("name")
                                        : fmt::format("equality{}", scene_.joints.size());
      j.def.body1 = BodyId{body("body1", true)};
      j.def.body2 = BodyId{body("body2", false)};
      const Pose& frame1 = body_frame_.at(e->Attribute("body1"));
      if (tag == "connect") {
        j.type = "ball";
        const auto anchor = vector(e, "", "", "anchor", 3);
        if (!anchor) fail(where(e), "a connect needs an anchor");
        j.def.anchor = frame1.toWorld(Vec3((*anchor)[0], (*anchor)[1], (*anchor)[2]));
      } else {
        j.type = "fixed";
        if (e->Attribute("relpose")) unused("weld relpose");
      }
      for (const char* a : {"solref", "solimp"})
        if (e->Attribute(a)) unused(fmt::format("equality {}", a));
      scene_.joints.push_back(std::move(j));
    }
  }

  std::filesystem::path path_;
  std::string file_;
  ImportOptions options_;
  tinyxml2::XMLDocument doc_;
  Scene scene_;
  bool degrees_ = true;  // MuJoCo's default
  std::string euler_sequence_ = "xyz";
  std::map<std::string, std::map<std::string, Attributes>> defaults_;
  std::map<std::string, int> body_index_;
  std::map<std::string, Pose> body_frame_;
  // Each named <joint>: its scene joint and coordinate there (actuators find it by name).
  std::map<std::string, std::pair<std::size_t, int>> joint_coordinate_;
  std::map<std::string, int> unused_;
  std::vector<io::StartOutside> started_outside_;  // joints moved inside their range
  std::filesystem::path mesh_folder_;              // <compiler meshdir> (or assetdir)
  bool strip_paths_ = false;
  bool exact_mesh_inertia_ = false;  // MuJoCo 2.2.2's default: the legacy rule
  std::string inertia_from_geom_ = "auto";
  std::array<double, 2> inertia_groups_{0.0, 5.0};
  std::map<std::string, const XMLElement*> mesh_assets_;
  std::map<std::string, Mesh> meshes_;  // read and weighed, by name
  int world_geoms_ = -1;
  int includes_ = 0;         // <include>s read
  std::uint64_t bytes_ = 0;  // bytes read: the model and every include read
  std::size_t spliced_ = 0;  // elements copied by includes
};

}  // namespace

Scene importMjcf(const std::filesystem::path& path, const ImportOptions& options) {
  return MjcfImporter(path, options).run();
}

}  // namespace linx
