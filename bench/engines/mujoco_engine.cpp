// MuJoCo 2.2.2 (Debian libmujoco-dev) adapter: MuJoCo's defaults (Newton solver, its default
// iterations and tolerance, pyramidal friction cone, soft constraints with the default
// solref/solimp, semi-implicit Euler); on mechanisms without contacts also RK4, at h and at h / 4
// (see mujocoVariants); in the Pareto table PGS at a given number of iterations.
//
// MuJoCo works in reduced (joint) coordinates, so the scene becomes a kinematic tree, written as an
// MJCF string and compiled by mj_loadXML from a virtual file system:
// - a breadth-first search from the world over the scene's joints makes the tree: a body's parent
//   is the body it was first reached from (a joint to the world or to a static body makes it a
//   child of the world); a dynamic body reached by no joint is the root of a tree of its own, with
//   a freejoint. A joint that meets an already placed body closes a loop and becomes an equality
//   constraint instead: a hinge becomes a `connect` (ball-and-socket) at its anchor, plus a second
//   `connect` 0.1 m along its axis unless the tree already keeps the two bodies' relative rotation
//   about that axis (every joint between them a parallel hinge or a slider, as in the planar
//   slider-crank); a ball becomes a `connect`. Loops closed by sliders or fixed joints, and limits
//   or motors on loop-closing joints, are refused (no scene has them).
// - every MuJoCo body frame is the scene body's principal frame (origin at the centre of mass),
//   with an explicit <inertial pos="0 0 0" diaginertia=...> (never computed from the geometry), so
//   pose() is xpos/xquat; a joint sits at the scene's anchor, expressed in the child's frame. When
//   the tree edge runs from body2 to body1 the joint axis is negated, so that MuJoCo's joint
//   coordinate is the scene's (body2 relative to body1).
// - hinge and slider limits become range + limited="true"; a motor becomes a velocity actuator
//   (force kv (target - qdot), clamped to +-max_force, ctrl = target). MuJoCo has no constraint
//   motor; kv is the dof's effective inertia at the start divided by h (kv = 1 / (h (M^-1)_ii)),
//   the gain that reaches the target in one step when the force is not clamped, like the constraint
//   motors of the other engines. Semi-implicit Euler applies it explicitly; the gain is stable as
//   long as the effective inertia stays above half of its starting value.
// - MJCF nests child bodies inside their parents and Debian's tinyxml2 refuses XML nested deeper
//   than 100 elements, so every 40 levels of bodies the subtree moves into a separate file of the
//   virtual file system, spliced in with <include> (MuJoCo merges included documents after
//   tinyxml2 has parsed each one, so the depth limit applies per file); a 1000-link chain is 25
//   files.
// - shapes are geoms centred in their body (MuJoCo's capsule lies along its local z, like the
//   scene's); static bodies are jointless bodies under the world (welded to it: MuJoCo never
//   collides them with each other or with the ground); the ground is a plane geom in the world.
//   Every geom has condim 3 (normal plus two-dimensional Coulomb friction, no torsional or rolling
//   friction) and friction "mu 0 0". MuJoCo already skips contacts between a body and its tree
//   parent; pairs joined by a loop-closing joint, or by a joint to a static body, get <exclude>.
// - MuJoCo 2.2.2 preallocates its constraint arrays in one mjData buffer whose size is an int:
//   dense njmax x nv Jacobians and a dense njmax x njmax matrix (efc_AR), zeroed (so resident) at
//   creation. Its defaults (njmax 500, nconmax 100) are far too small for the scenes, so the
//   adapter sizes nconmax from the shapes (a per-shape budget of contacts, below) and njmax from it
//   (4 rows per pyramidal condim-3 contact, 3 per connect, 1 per limit), and refuses a scene whose
//   buffer would pass 2 GiB, which MuJoCo cannot allocate. A run that outgrows the budget fails
//   (MuJoCo would silently drop contacts). The stack keeps MuJoCo's default size, capped where
//   MuJoCo's int arithmetic would overflow.
// - MuJoCo resets a simulation whose accelerations become non-finite or huge and goes on; the
//   adapter then reports NaN poses, so the accuracy figure shows the blow-up. MuJoCo's default
//   error handler waits for Enter and exits; the adapter's turns errors into exceptions.
// - step() is mj_step2 followed by mj_step1 (the construction calls mj_step1 once): together
//   exactly mj_step for the Euler integrator, but it leaves xpos/xquat at the new positions for
//   pose() (after mj_step they would still describe the start of the step). RK4 runs only through
//   mj_step, which leaves them at an inner stage: pose() then calls mj_kinematics first, outside
//   the timed step (the next mj_step computes the same again).
#include "engine.hpp"
#include "scene_tree.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace bench {
namespace {

// Levels of nested bodies per MJCF file (tinyxml2 in Debian stops at element depth 100).
constexpr int kLevelsPerFile = 40;
// Distance along a loop-closing hinge's axis of its second connect point (m).
constexpr double kSecondConnectOffset = 0.1;
// Contacts budgeted per dynamic body with a shape (a contact between two bodies, or with a static
// body or the ground, is counted once, at the dynamic body): a box resting on two others or on the
// ground has 2 x 4 points (measured: 8 per box in the base-10 pyramid, 8.5 at most in the base-20
// one), a sphere in a settled pile about 2.6 (320 contacts for 125 poured spheres, 555 for 216), a
// capsule of a ragdoll on the ground 2 at most (63 contacts for 10 ragdolls, 547 for 100).
// Exceeding the budget fails the run.
constexpr int kContactsPerBox = 10;
constexpr int kContactsPerSphere = 4;
constexpr int kContactsPerCapsule = 2;
constexpr int kRowsPerContact = 4;  // pyramidal cone, condim 3: 2 (condim - 1) rows
// MuJoCo's mjData buffer size is an int (bytes).
constexpr double kMaxBufferBytes = 2147483647.0;

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string vec(const Vec3& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}
std::string quat(const Quat& q) {  // MuJoCo order: w x y z
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}
std::string bodyName(int i) {
  std::string name = std::to_string(i);  // "b" + to_string trips GCC 12's -Wrestrict at -O3
  name.insert(name.begin(), 'b');
  return name;
}

/// MJCF text, split into files for the virtual file system.
struct Mjcf {
  std::vector<std::pair<std::string, std::string>> files;  ///< name, content; files[0] is the model
};

class Writer {
 public:
  Writer(const Scene& scene, const SceneTree& tree, Mjcf& out)
      : scene_(scene), tree_(tree), out_(out) {}

  /// Writes body v (and its subtree) into `xml`, whose bodies are nested `level` deep.
  void body(int v, int level, std::string& xml) {
    if (level >= kLevelsPerFile) {
      const std::string name = std::to_string(out_.files.size()).insert(0, "subtree") + ".xml";
      out_.files.emplace_back(name, std::string());
      const std::size_t index = out_.files.size() - 1;
      std::string sub = "<mujoco>";
      body(v, 0, sub);
      sub += "</mujoco>";
      out_.files[index].second = std::move(sub);
      xml += "<include file='" + name + "'/>";
      return;
    }
    const auto vi = static_cast<std::size_t>(v);
    const Body& b = scene_.bodies[vi];
    const int p = tree_.parent[vi];
    Vec3 pos = b.position;
    Quat q = b.orientation.normalized();
    if (p != kWorld) {
      const Body& pb = scene_.bodies[static_cast<std::size_t>(p)];
      const Quat pq = pb.orientation.normalized();
      pos = pq.conjugate() * (b.position - pb.position);
      q = pq.conjugate() * q;
    }
    xml += "<body name='" + bodyName(v) + "' pos='" + vec(pos) + "' quat='" + quat(q) + "'>";
    if (!b.is_static) {
      xml +=
          "<inertial pos='0 0 0' mass='" + num(b.mass) + "' diaginertia='" + vec(b.inertia) + "'/>";
    }
    if (tree_.free_root[vi]) {
      xml += "<freejoint name='free" + std::to_string(v) + "'/>";
    } else if (tree_.joint[vi] >= 0) {
      joint(v, xml);
    }
    geom(b.shape, xml);
    sites(v, xml);
    for (int c : tree_.children[vi]) body(c, level + 1, xml);
    xml += "</body>";
  }

 private:
  void joint(int v, std::string& xml) const {
    const auto vi = static_cast<std::size_t>(v);
    const int j = tree_.joint[vi];
    const Joint& jt = scene_.joints[static_cast<std::size_t>(j)];
    if (jt.kind == Joint::Kind::Fixed) return;  // a jointless child is welded to its parent
    const Body& b = scene_.bodies[vi];
    const Quat bq = b.orientation.normalized();
    const Vec3 anchor = bq.conjugate() * (jt.anchor - b.position);
    const Vec3 axis = bq.conjugate() * (tree_.flipped[vi] ? -jt.axis : jt.axis).normalized();
    const char* type = jt.kind == Joint::Kind::Hinge    ? "hinge"
                       : jt.kind == Joint::Kind::Slider ? "slide"
                                                        : "ball";
    xml += "<joint name='j" + std::to_string(j) + "' type='" + type + "' pos='" + vec(anchor) + "'";
    if (jt.kind != Joint::Kind::Ball) xml += " axis='" + vec(axis) + "'";
    if (jt.limits) {
      xml += " limited='true' range='" + num(jt.limits->lower) + " " + num(jt.limits->upper) + "'";
    }
    xml += "/>";
  }

  /// A site at each end of a spring on body v (-1: the world), named s<spring>a / s<spring>b, in
  /// the body's frame.
  void sites(int v, std::string& xml) const {
    for (std::size_t k = 0; k < scene_.springs.size(); ++k) {
      const Spring& sp = scene_.springs[k];
      for (const auto& [body, point, end] :
           {std::tuple{sp.body1, sp.anchor1, 'a'}, std::tuple{sp.body2, sp.anchor2, 'b'}}) {
        if (body != v) continue;
        Vec3 local = point;
        if (v >= 0) {
          const Body& b = scene_.bodies[static_cast<std::size_t>(v)];
          local = b.orientation.normalized().conjugate() * (point - b.position);
        }
        xml += "<site name='s" + std::to_string(k) + end + "' pos='" + vec(local) + "'/>";
      }
    }
  }

 public:
  /// The springs as spatial tendons between their sites: MuJoCo's passive tendon force
  /// -stiffness (length - springlength) - damping length'.
  void tendons(std::string& xml) const {
    if (scene_.springs.empty()) return;
    xml += "<tendon>";
    for (std::size_t k = 0; k < scene_.springs.size(); ++k) {
      const Spring& sp = scene_.springs[k];
      const std::string n = std::to_string(k);
      xml += "<spatial name='t" + n + "' stiffness='" + num(sp.stiffness) + "' damping='" +
             num(sp.damping) + "' springlength='" + num(sp.rest) + "'><site site='s" + n +
             "a'/><site site='s" + n + "b'/></spatial>";
    }
    xml += "</tendon>";
  }
  void worldSites(std::string& xml) const { sites(-1, xml); }

 private:
  static void geom(const Shape& s, std::string& xml) {
    switch (s.kind) {
      case Shape::Kind::None:
        return;
      case Shape::Kind::Sphere:
        xml += "<geom type='sphere' size='" + num(s.radius) + "'/>";
        return;
      case Shape::Kind::Box:
        xml += "<geom type='box' size='" + vec(s.half_extents) + "'/>";
        return;
      case Shape::Kind::Capsule:
        xml += "<geom type='capsule' size='" + num(s.radius) + " " + num(s.half_length) + "'/>";
        return;
    }
  }

  const Scene& scene_;
  const SceneTree& tree_;
  Mjcf& out_;
};

/// What a variant changes in MuJoCo's defaults.
struct Options {
  int solver = -1;               ///< mjtSolver; -1: MuJoCo's default (Newton)
  int iterations = 0;            ///< the solver's iteration cap; 0: MuJoCo's default (100)
  int integrator = mjINT_EULER;  ///< mjINT_EULER, mjINT_RK4 or mjINT_IMPLICIT
  int substeps = 1;              ///< MuJoCo steps of scene.timestep / substeps per step()
};

/// The integrator as MJCF's <option integrator> names it.
const char* integratorName(int integrator) {
  return integrator == mjINT_RK4 ? "RK4" : integrator == mjINT_IMPLICIT ? "implicit" : "Euler";
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    std::free(v);
  }
};

class MujocoEngine final : public Engine {
 public:
  MujocoEngine(const Scene& scene, const Options& options);
  void step() override {
    mjData* d = data_.get();
    const double t = d->time + substeps_ * model_->opt.timestep;
    for (int k = 0; k < substeps_; ++k) {
      if (model_->opt.integrator != mjINT_EULER) {
        // RK4 and implicit only through mj_step: xpos is left from an inner stage (RK4)
        mj_step(model_.get(), d);
        posed_ = false;
        moving_ = false;
      } else {
        mj_step2(model_.get(), d);  // Euler, then the next step's positions
        mj_step1(model_.get(), d);
      }
    }
    // MuJoCo does not stop on these. A diverged simulation (non-finite or huge accelerations) is
    // reset to the initial state and goes on: from then on pose() reports NaN, which the accuracy
    // figure shows as a blown-up engine (MuJoCo's warning, on stderr, gives the time). Contacts or
    // constraint rows beyond the preallocated arrays are dropped, which would be another
    // simulation: the run fails instead.
    if (d->warning[mjWARN_BADQACC].number + d->warning[mjWARN_BADQVEL].number +
            d->warning[mjWARN_BADQPOS].number >
        0) {
      diverged_ = true;
    }
    if (d->warning[mjWARN_CONTACTFULL].number + d->warning[mjWARN_CNSTRFULL].number > 0) {
      throw std::runtime_error("MuJoCo ran out of its preallocated contacts (nconmax " +
                               std::to_string(model_->nconmax) + ") or constraint rows (njmax " +
                               std::to_string(model_->njmax) + ") at t = " + std::to_string(t) +
                               " s");
    }
  }
  Pose pose(int i) const override {
    if (diverged_) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return Pose{Vec3::Constant(nan), Quat(nan, nan, nan, nan)};
    }
    if (!posed_) {  // after an RK4 step: the positions' kinematics, untimed (mj_step redoes it)
      mj_kinematics(model_.get(), data_.get());
      posed_ = true;
    }
    const int id = body_id_[static_cast<std::size_t>(i)];
    const mjtNum* p = data_->xpos + 3 * id;
    const mjtNum* q = data_->xquat + 4 * id;
    return Pose{Vec3(p[0], p[1], p[2]), Quat(q[0], q[1], q[2], q[3])};
  }
  // mj_objectVelocity of the body (mjOBJ_BODY: at xipos, its inertial frame, which the MJCF puts
  // at the body frame's origin, the centre of mass) in the world's orientation (flg_local 0):
  // (angular, linear). It reads cvel and subtree_com, which mj_step1 leaves current after an Euler
  // step; after an RK4 step they are an inner stage's, so they are recomputed first (untimed; the
  // next mj_step computes them again).
  Twist velocity(int i) const override {
    if (diverged_) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return Twist{Vec3::Constant(nan), Vec3::Constant(nan)};
    }
    if (!moving_) {
      if (!posed_) {
        mj_kinematics(model_.get(), data_.get());
        posed_ = true;
      }
      mj_comPos(model_.get(), data_.get());
      mj_comVel(model_.get(), data_.get());
      moving_ = true;
    }
    const int id = body_id_[static_cast<std::size_t>(i)];
    mjtNum res[6];
    mj_objectVelocity(model_.get(), data_.get(), mjOBJ_BODY, id, res, 0);
    return Twist{Vec3(res[3], res[4], res[5]), Vec3(res[0], res[1], res[2])};
  }

 private:
  std::unique_ptr<mjModel, ModelDeleter> model_;
  std::unique_ptr<mjData, DataDeleter> data_;
  std::vector<int> body_id_;
  bool diverged_ = false;
  int substeps_ = 1;
  mutable bool posed_ = true;   ///< xpos, xquat are the current positions'
  mutable bool moving_ = true;  ///< cvel, subtree_com are the current state's
};

/// MuJoCo's default warning handler prints to stdout and appends to MUJOCO_LOG.TXT in the current
/// directory; step() turns the warnings that matter into exceptions, so they go to stderr only.
void warningToStderr(const char* message) {
  std::fprintf(stderr, "MuJoCo warning: %s\n", message);
}
/// MuJoCo's default error handler prints, waits for Enter on stdin and exits; an exception (it
/// crosses MuJoCo's C frames, which have unwind tables on x86-64, as in MuJoCo's own Python
/// bindings) lets the runner report the failure instead.
[[noreturn]] void errorToException(const char* message) {
  throw std::runtime_error(std::string("MuJoCo error: ") + message);
}

MujocoEngine::MujocoEngine(const Scene& scene, const Options& options)
    : substeps_(options.substeps) {
  mju_user_warning = warningToStderr;
  mju_user_error = errorToException;
  const SceneTree tree = buildSceneTree(scene, true);

  // Loop closures, exclusions, actuators, and the sizes of the constraint arrays.
  std::string equality, exclude, actuator;
  int eq_rows = 0, limit_rows = 0, ncon = 0, nv = 0;
  for (int j : tree.closures) {
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    if (jt.limits || jt.motor) {
      throw Unsupported("a limit or motor on a joint closing a loop (MuJoCo: equality constraint)");
    }
    if (jt.kind == Joint::Kind::Slider || jt.kind == Joint::Kind::Fixed) {
      throw Unsupported("a slider or fixed joint closing a loop is not mapped to MuJoCo");
    }
    // body1 of the connect must be a body; body2 may be the world (omitted).
    int b1 = jt.body1, b2 = jt.body2;
    if (b1 < 0) std::swap(b1, b2);
    const Body& body1 = scene.bodies[static_cast<std::size_t>(b1)];
    const Quat q1 = body1.orientation.normalized();
    const auto connect = [&](const Vec3& world_point) {
      equality += "<connect body1='" + bodyName(b1) + "'";
      if (b2 >= 0) equality += " body2='" + bodyName(b2) + "'";
      equality += " anchor='" + vec(q1.conjugate() * (world_point - body1.position)) + "'/>";
      eq_rows += 3;
    };
    connect(jt.anchor);
    if (jt.kind == Joint::Kind::Hinge && !rotationKeptAbout(scene, tree, treeNode(scene, jt.body1),
                                                            treeNode(scene, jt.body2), jt.axis)) {
      connect(jt.anchor + kSecondConnectOffset * jt.axis.normalized());
    }
  }
  for (std::size_t j = 0; j < scene.joints.size(); ++j) {
    const Joint& jt = scene.joints[j];
    const bool closure =
        std::binary_search(tree.closures.begin(), tree.closures.end(), static_cast<int>(j));
    const bool to_static =
        (jt.body1 >= 0 && scene.bodies[static_cast<std::size_t>(jt.body1)].is_static) ||
        (jt.body2 >= 0 && scene.bodies[static_cast<std::size_t>(jt.body2)].is_static);
    if ((closure || to_static) && jt.body1 >= 0 && jt.body2 >= 0) {
      exclude += "<exclude body1='" + bodyName(jt.body1) + "' body2='" + bodyName(jt.body2) + "'/>";
    }
    if (closure) continue;
    if (jt.limits) {
      if (jt.kind == Joint::Kind::Ball || jt.kind == Joint::Kind::Fixed) {
        throw Unsupported("limits on a ball or fixed joint are not mapped to MuJoCo");
      }
      limit_rows += 1;
    }
    if (jt.motor) {
      if (jt.kind != Joint::Kind::Hinge && jt.kind != Joint::Kind::Slider) {
        throw Unsupported("a motor on a ball or fixed joint is not mapped to MuJoCo");
      }
      if (treeNode(scene, jt.body1) == treeNode(scene, jt.body2)) continue;  // joins nothing
      actuator += "<velocity name='m" + std::to_string(j) + "' joint='j" + std::to_string(j) +
                  "' kv='1' ctrllimited='false' forcelimited='true' forcerange='" +
                  num(-jt.motor->max_force) + " " + num(jt.motor->max_force) + "'/>";
    }
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if (tree.free_root[i]) nv += 6;
    if (!b.is_static && tree.joint[i] >= 0) {
      switch (scene.joints[static_cast<std::size_t>(tree.joint[i])].kind) {
        case Joint::Kind::Hinge:
        case Joint::Kind::Slider:
          nv += 1;
          break;
        case Joint::Kind::Ball:
          nv += 3;
          break;
        case Joint::Kind::Fixed:
          break;
      }
    }
    if (b.is_static) continue;
    switch (b.shape.kind) {
      case Shape::Kind::None:
        break;
      case Shape::Kind::Sphere:
        ncon += kContactsPerSphere;
        break;
      case Shape::Kind::Box:
        ncon += kContactsPerBox;
        break;
      case Shape::Kind::Capsule:
        ncon += kContactsPerCapsule;
        break;
    }
  }
  const int nconmax = std::max(ncon, 1);
  const int njmax = std::max(eq_rows + limit_rows + kRowsPerContact * ncon, 1);
  // mjData buffer: efc_J, efc_JT (mjtNum) and their column indices (int), njmax x nv each, plus
  // efc_AR (mjtNum) and its column indices (int), njmax x njmax; the rest is small.
  const double bytes = 24.0 * njmax * std::max(nv, 1) + 12.0 * njmax * static_cast<double>(njmax) +
                       600.0 * nconmax + 1e6;
  if (bytes > 0.98 * kMaxBufferBytes) {
    char why[300];
    std::snprintf(
        why, sizeof why,
        "MuJoCo 2.2.2 preallocates dense njmax x nv and njmax x njmax constraint arrays in "
        "one int-sized buffer: %d dofs and %d budgeted constraint rows need %.1f GB > 2 GiB",
        nv, njmax, bytes * 1e-9);
    throw Unsupported(why);
  }
  // Stack: MuJoCo's own heuristic, 5 (njmax + neq + nv)^2 mjtNums (plus 20 per element), is kept:
  // it is only reserved (malloc, not touched; the Newton solver uses about 3 to 5 nv^2). It is
  // computed in int, though, and would overflow for large models, so there it is capped at 2^30
  // mjtNums (8 GiB of address space).
  constexpr double kStackCap = 1073741824.0;
  const bool cap_stack = 5.0 * std::pow(njmax + eq_rows / 3 + nv, 2.0) > 0.9 * kStackCap;

  // The model.
  Mjcf mjcf;
  mjcf.files.emplace_back("model.xml", std::string());
  std::string xml = "<mujoco model='bench'><compiler angle='radian'/>";
  xml += "<option timestep='" + num(scene.timestep / options.substeps) + "' gravity='" +
         vec(scene.gravity) + "' integrator='" + integratorName(options.integrator) + "'/>";
  xml += "<size njmax='" + std::to_string(njmax) + "' nconmax='" + std::to_string(nconmax) + "'";
  if (cap_stack) xml += " nstack='" + num(kStackCap) + "'";
  xml += "/>";
  xml += "<default><geom condim='3' friction='" + num(scene.friction) + " 0 0'/></default>";
  xml += "<worldbody>";
  if (scene.ground_z) {
    xml += "<geom name='ground' type='plane' size='0 0 1' pos='0 0 " + num(*scene.ground_z) + "'/>";
  }
  Writer writer(scene, tree, mjcf);
  writer.worldSites(xml);
  for (int r : tree.roots) writer.body(r, 0, xml);
  xml += "</worldbody>";
  writer.tendons(xml);
  if (!exclude.empty()) xml += "<contact>" + exclude + "</contact>";
  if (!equality.empty()) xml += "<equality>" + equality + "</equality>";
  if (!actuator.empty()) xml += "<actuator>" + actuator + "</actuator>";
  xml += "</mujoco>";
  mjcf.files[0].second = std::move(xml);
  if (mjcf.files.size() > mjMAXVFS) throw Unsupported("the MJCF needs more than mjMAXVFS files");

  {
    // mjVFS holds 2,000 file names of 1,000 characters: keep it off the stack.
    std::unique_ptr<mjVFS, VfsDeleter> vfs(static_cast<mjVFS*>(std::malloc(sizeof(mjVFS))));
    if (!vfs) throw std::bad_alloc();
    mj_defaultVFS(vfs.get());
    for (const auto& [name, text] : mjcf.files) {
      if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(text.size())) != 0) {
        throw std::runtime_error("mj_makeEmptyFileVFS failed for " + name);
      }
      std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name.c_str())], text.data(), text.size());
    }
    char error[1000] = "";
    model_.reset(mj_loadXML("model.xml", vfs.get(), error, sizeof error));
    if (!model_) throw std::runtime_error(std::string("mj_loadXML: ") + error);
  }
  mjModel* m = model_.get();
  if (options.solver >= 0) m->opt.solver = options.solver;
  if (options.iterations > 0) m->opt.iterations = options.iterations;
  data_.reset(mj_makeData(m));
  if (!data_) throw std::runtime_error("mj_makeData failed");
  mjData* d = data_.get();

  body_id_.resize(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    body_id_[i] = mj_name2id(m, mjOBJ_BODY, bodyName(static_cast<int>(i)).c_str());
    if (body_id_[i] < 0)
      throw std::runtime_error("MuJoCo body " + bodyName(static_cast<int>(i)) + " missing");
  }

  // Initial velocities: a freejoint's are the linear velocity (world) and the angular velocity in
  // the body frame; a hinge or slider's the relative rate about / along its axis.
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if (b.is_static) continue;
    if (tree.free_root[i]) {
      const int jid = mj_name2id(m, mjOBJ_JOINT, (std::to_string(i).insert(0, "free")).c_str());
      mjtNum* v = d->qvel + m->jnt_dofadr[jid];
      const Vec3 w = b.orientation.normalized().conjugate() * b.angular_velocity;
      for (int k = 0; k < 3; ++k) {
        v[k] = b.velocity[k];
        v[3 + k] = w[k];
      }
      continue;
    }
    const int j = tree.joint[i];
    if (j < 0) continue;
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    const int jid = mj_name2id(m, mjOBJ_JOINT, (std::to_string(j).insert(0, "j")).c_str());
    if (jid < 0) continue;  // fixed
    const int p = tree.parent[i];
    const Body* pb = p == kWorld ? nullptr : &scene.bodies[static_cast<std::size_t>(p)];
    const Vec3 pw = pb ? pb->angular_velocity : Vec3::Zero();
    const Vec3 axis = (tree.flipped[i] ? -jt.axis : jt.axis).normalized();
    mjtNum* v = d->qvel + m->jnt_dofadr[jid];
    switch (jt.kind) {
      case Joint::Kind::Hinge:
        v[0] = (b.angular_velocity - pw).dot(axis);
        break;
      case Joint::Kind::Slider: {
        const Vec3 pv =
            pb ? Vec3(pb->velocity + pw.cross(b.position - pb->position)) : Vec3::Zero();
        v[0] = (b.velocity - pv).dot(axis);
        break;
      }
      case Joint::Kind::Ball: {
        const Vec3 w = b.orientation.normalized().conjugate() * (b.angular_velocity - pw);
        for (int k = 0; k < 3; ++k) v[k] = w[k];
        break;
      }
      case Joint::Kind::Fixed:
        break;
    }
  }

  mj_step1(m, d);  // positions and velocities: kinematics, mass matrix, collisions, constraints

  // Motors: ctrl = target velocity, kv = effective inertia of the dof at the start / h.
  for (int a = 0; a < m->nu; ++a) {
    const char* name = mj_id2name(m, mjOBJ_ACTUATOR, a);
    const int j = std::atoi(name + 1);
    const Joint& jt = scene.joints[static_cast<std::size_t>(j)];
    const int dof = m->jnt_dofadr[m->actuator_trnid[2 * a]];
    std::vector<mjtNum> unit(static_cast<std::size_t>(m->nv), 0.0),
        column(static_cast<std::size_t>(m->nv), 0.0);
    unit[static_cast<std::size_t>(dof)] = 1.0;
    mj_solveM(m, d, column.data(), unit.data(), 1);
    const double kv = 1.0 / (m->opt.timestep * column[static_cast<std::size_t>(dof)]);
    m->actuator_gainprm[mjNGAIN * a] = kv;
    m->actuator_biasprm[mjNBIAS * a + 2] = -kv;
    d->ctrl[a] = jt.motor->target_velocity;
  }
}

std::string settingsString(const Options& options) {
  mjOption opt;
  mj_defaultOption(&opt);
  if (options.solver >= 0) opt.solver = options.solver;
  if (options.iterations > 0) opt.iterations = options.iterations;
  mjtNum solref[mjNREF], solimp[mjNIMP];
  mj_defaultSolRefImp(solref, solimp);
  const char* solver = opt.solver == mjSOL_NEWTON ? "Newton"
                       : opt.solver == mjSOL_CG   ? "CG"
                                                  : "PGS";
  const char* cone = opt.cone == mjCONE_PYRAMIDAL ? "pyramidal" : "elliptic";
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%s %d it tol %g, %s cone, %s, solref %g %g, solimp %g %g %g %g %g, condim 3; "
                "loops: connect; motor: velocity actuator kv = M_eff/h",
                solver, opt.iterations, opt.tolerance, cone, integratorName(options.integrator),
                solref[0], solref[1], solimp[0], solimp[1], solimp[2], solimp[3], solimp[4]);
  std::string out = buf;
  if (options.substeps > 1) {
    out += ", ";
    out += std::to_string(options.substeps);
    out += " substeps (h / ";
    out += std::to_string(options.substeps);
    out += ")";
  }
  return out;
}

Variant variant(const Options& options, std::string knob) {
  Variant v;
  v.engine = "MuJoCo";
  v.settings = settingsString(options);
  v.make = [options](const Scene& scene) -> std::unique_ptr<Engine> {
    return std::make_unique<MujocoEngine>(scene, options);
  };
  v.knob = std::move(knob);
  return v;
}

}  // namespace

std::vector<Variant> mujocoVariants(const Scene& scene) {
  std::vector<Variant> out{variant(Options{}, "default: Newton, Euler")};
  // Mechanisms (joints, no contacts): semi-implicit Euler gains energy on the whipping 10- and
  // 100-link chains at h = 1/240 and diverges (at 1.6 and 1.4 s), RK4 does not; the 1000:1
  // chains are stiff (their light links swing about the tension of the heavy one) and diverge at
  // h = 1/240 with either integrator, but not with RK4 at h / 4. MuJoCo's implicit integrator
  // (implicit in the velocity-dependent forces only) diverges on the 10-link chain too. The
  // ragdolls keep Euler alone: they do not diverge. See docs/performance.md.
  const bool contacts = scene.ground_z.has_value() ||
                        std::any_of(scene.bodies.begin(), scene.bodies.end(), [](const Body& b) {
                          return b.shape.kind != Shape::Kind::None;
                        });
  if (!scene.joints.empty() && !contacts) {
    out.push_back(variant(Options{-1, 0, mjINT_RK4, 1}, "Newton, RK4"));
    out.push_back(variant(Options{-1, 0, mjINT_RK4, 4}, "Newton, RK4, 4 substeps"));
  }
  return out;
}

// The integrator table: Euler, implicit and RK4, each at h and at smaller steps (substeps), the
// default solver. MuJoCo's own tolerance (Newton's) leaves a mechanism's loop-closing connects
// soft: that error is MuJoCo's at every step size. RK4 is swept by factors of two up to h / 16,
// so that the fastest row as accurate as linx's costs at most about twice what RK4 would at
// exactly linx's error.
std::vector<Variant> mujocoIntegrators(const Scene& /*scene*/) {
  std::vector<Variant> out;
  const auto row = [&](int integrator, int substeps) {
    std::string knob = std::string("Newton, ") + integratorName(integrator);
    if (substeps > 1) knob += ", h / " + std::to_string(substeps);
    out.push_back(variant(Options{-1, 0, integrator, substeps}, std::move(knob)));
  };
  row(mjINT_EULER, 1);
  row(mjINT_EULER, 16);
  row(mjINT_IMPLICIT, 1);
  row(mjINT_IMPLICIT, 16);
  for (int substeps : {1, 2, 4, 8, 16, 64}) row(mjINT_RK4, substeps);
  return out;
}

// PGS is swept, as the other engines' projected Gauss-Seidel or sequential-impulse solvers are;
// the default solver (Newton, which stops at its tolerance) keeps its own row.
std::vector<Variant> mujocoSweep(const Scene& /*scene*/, const std::vector<int>& counts) {
  mjOption defaults;
  mj_defaultOption(&defaults);
  std::string knob("default: Newton, mjOption::iterations = ");
  knob += std::to_string(defaults.iterations);
  std::vector<Variant> out{variant(Options{}, std::move(knob))};
  for (int iterations : counts) {
    std::string pgs("PGS, mjOption::iterations = ");
    pgs += std::to_string(iterations);
    out.push_back(variant(Options{mjSOL_PGS, iterations, mjINT_EULER, 1}, std::move(pgs)));
  }
  return out;
}

}  // namespace bench
