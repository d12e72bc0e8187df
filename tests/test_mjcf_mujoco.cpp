// MJCF import against MuJoCo itself, the reference solution: the same file loaded by both.
// - A chain with several joints in one body (hinges at offset points, a slide), armature,
//   joint springs about springref, damping and ref, position, velocity and motor actuators at zero
//   control, swung by gravity: both engines' bodies follow
//   the same path (each converges at its own first order in h; at h = 0.1 ms they agree to the
//   step's error). Armature on hinges only: on a slide carried round by its parent, linx's
//   armature feels the centripetal acceleration (docs/joints.md, "Armature").
// - MuJoCo's humanoid sample (libmujoco-samples): every body's mass, centre of mass and inertia as
//   MuJoCo computes them from the geoms; it falls and lies down with its joints held.
#include "support.hpp"

#include <linx/import.hpp>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <fmt/format.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace linx {
namespace {

namespace fs = std::filesystem;

struct MujocoModel {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  explicit MujocoModel(const fs::path& path) {
    char error[1000] = "";
    model = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
    if (!model) throw std::runtime_error(error);
    data = mj_makeData(model);
    mj_forward(model, data);
  }
  ~MujocoModel() {
    mj_deleteData(data);
    mj_deleteModel(model);
  }
  MujocoModel(const MujocoModel&) = delete;
  MujocoModel& operator=(const MujocoModel&) = delete;

  int body(const std::string& name) const { return mj_name2id(model, mjOBJ_BODY, name.c_str()); }
  Vec3 centre(int b) const {
    return Vec3(data->xipos[3 * b], data->xipos[3 * b + 1], data->xipos[3 * b + 2]);
  }
  // The inertia about the centre of mass, world axes.
  Mat3 inertia(int b) const {
    Mat3 r;
    for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = data->ximat[9 * b + i];
    const Vec3 principal(model->body_inertia[3 * b], model->body_inertia[3 * b + 1],
                         model->body_inertia[3 * b + 2]);
    return r * principal.asDiagonal() * r.transpose();
  }
  // The principal moments, smallest first.
  Vec3 moments(int b) const {
    Vec3 m(model->body_inertia[3 * b], model->body_inertia[3 * b + 1],
           model->body_inertia[3 * b + 2]);
    std::sort(m.begin(), m.end());
    return m;
  }
};

// A body's principal moments, smallest first, against MuJoCo's body `b`'s (relative).
double momentsError(const Body& body, const MujocoModel& mj, int b) {
  const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(body.inertiaWorld()).eigenvalues();
  return (moments - mj.moments(b)).norm() / mj.moments(b).norm();
}

const char* kChain = R"(<mujoco model="serial chain">
  <compiler angle="degree"/>
  <option timestep="0.0001" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="upper" pos="0 0 1" euler="10 20 0">
      <joint name="h1" type="hinge" pos="0 0 0.05" axis="0 1 0" damping="0.05" armature="0.01"/>
      <joint name="h2" type="hinge" pos="0.02 0 0" axis="1 0 0.5" stiffness="2" springref="10"
             ref="5" armature="0.02"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 -0.3" size="0.04"/>
      <body name="lower" pos="0.3 0 -0.3">
        <joint name="s" type="slide" axis="1 0 -1" stiffness="50" damping="0.5"/>
        <joint name="h3" type="hinge" axis="0 1 1" armature="0.005"/>
        <geom type="box" size="0.05 0.1 0.02" pos="0 0.1 0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position joint="h1" kp="3" gear="2"/>
    <velocity joint="s" kv="2" gear="1.5"/>
    <motor joint="h3" gear="2"/>
  </actuator>
</mujoco>)";

TEST(MjcfAgainstMujoco, SeveralJointsInOneBodyMoveAsInMujoco) {
  test::TempFolder folder("linx_mjcf_mujoco_chain");
  const fs::path path = folder.write("chain.xml", kChain);
  MujocoModel mj(path);
  const Scene scene = importMjcf(path);
  World world = buildWorld(scene);
  ASSERT_EQ(world.jointCount(), 2);  // a serial joint of 2 hinges in each body
  const double h = scene.settings.timestep;
  ASSERT_EQ(h, mj.model->opt.timestep);
  double worst = 0.0, travel = 0.0;
  const Vec3 start = world.body(*world.findBody("lower")).position();
  for (int i = 0; i < 5000; ++i) {  // 0.5 s
    world.step();
    mj_step(mj.model, mj.data);
    for (const std::string name : {"upper", "lower"}) {
      const Vec3 x = world.body(*world.findBody(name)).position();
      worst = std::max(worst, (x - mj.centre(mj.body(name))).norm());
    }
    travel = std::max(travel, (world.body(*world.findBody("lower")).position() - start).norm());
  }
  std::printf(
      "0.5 s: bodies' centres differ from MuJoCo's by %.2e m at most (the lower body "
      "travelled %.3f m), joint error %.2e\n",
      worst, travel, world.maxJointError());
  EXPECT_GT(travel, 0.1);
  EXPECT_LT(worst, 1e-3 * travel);
  EXPECT_LT(world.maxJointError(), 1e-9);
}

const fs::path kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";

TEST(MjcfAgainstMujoco, HumanoidMassesAreMujocos) {
  if (!fs::exists(kHumanoid))
    GTEST_SKIP() << kHumanoid << " is missing (Debian's libmujoco-samples)";
  MujocoModel mj(kHumanoid);
  const Scene scene = importMjcf(kHumanoid);
  World world = buildWorld(scene);
  double mass = 0.0, worst_mass = 0.0, worst_centre = 0.0, worst_inertia = 0.0;
  int bodies = 0;
  for (const BodyDef& def : scene.bodies) {
    if (def.is_static) continue;
    const int b = mj.body(def.name);
    ASSERT_GE(b, 0) << def.name;
    const Body& body = world.body(*world.findBody(def.name));
    mass += body.mass();
    worst_mass = std::max(worst_mass, std::abs(body.mass() / mj.model->body_mass[b] - 1.0));
    worst_centre = std::max(worst_centre, (body.position() - mj.centre(b)).norm());
    worst_inertia = std::max(worst_inertia,
                             (body.inertiaWorld() - mj.inertia(b)).norm() / mj.inertia(b).norm());
    ++bodies;
  }
  double mj_mass = 0.0;
  for (int b = 1; b < mj.model->nbody; ++b) mj_mass += mj.model->body_mass[b];
  std::printf(
      "%d bodies, %.6f kg (MuJoCo %.6f kg); largest differences: mass %.2e, centre "
      "%.2e m, inertia %.2e (relative)\n",
      bodies, mass, mj_mass, worst_mass, worst_centre, worst_inertia);
  EXPECT_EQ(bodies, mj.model->nbody - 1);
  EXPECT_LT(worst_mass, 1e-12);
  EXPECT_LT(worst_centre, 1e-12);
  EXPECT_LT(worst_inertia, 1e-12);
}

// Ellipsoid geoms, turned and offset: each body's mass, centre and inertia as MuJoCo computes them
// from the geoms (humanoid100's hands are ellipsoids). One geom a body: with several whose
// principal axes differ, MuJoCo's body inertia differs from linx's (the exact sum, checked in
// test_mass_properties) by up to 7e-8 relative (two turned boxes), likely its eigen decomposition.
TEST(MjcfAgainstMujoco, EllipsoidMassesAreMujocos) {
  const test::TempFolder folder("linx_mjcf_ellipsoid");
  const fs::path path = folder.write("eggs.xml", R"(<mujoco>
  <worldbody>
    <body name="a" pos="0 0 1" euler="10 20 30">
      <freejoint/>
      <geom type="ellipsoid" size="0.3 0.2 0.1" pos="0.1 0 0" euler="0 40 10" density="700"/>
      <body name="b" pos="0.5 0 0">
        <joint type="hinge" axis="0 1 0"/>
        <geom type="ellipsoid" size="0.05 0.12 0.07" quat="0.9 0.1 0.3 0.2"/>
      </body>
    </body>
  </worldbody>
</mujoco>)");
  MujocoModel mj(path);
  const Scene scene = importMjcf(path);
  World world = buildWorld(scene);
  for (const char* name : {"a", "b"}) {
    SCOPED_TRACE(name);
    const int b = mj.body(name);
    const Body& body = world.body(*world.findBody(name));
    EXPECT_NEAR(body.mass() / mj.model->body_mass[b], 1.0, 1e-12);
    EXPECT_LT((body.position() - mj.centre(b)).norm(), 1e-12);
    EXPECT_LT((body.inertiaWorld() - mj.inertia(b)).norm() / mj.inertia(b).norm(), 1e-12);
  }
}

// An arm held by its actuators at their controls' nearest values to zero, as MuJoCo holds it at its
// start: <general> position servos in Menagerie's form (gain kp, bias -kp L - kv L', from a
// default class), one with a gear and a control range that excludes zero (its control is the
// range's lower end), and one on a slide. Gravity sags each joint from its target
// by its load over its stiffness; after 2 s both engines hold the same pose.
TEST(MjcfAgainstMujoco, ArmHeldByGeneralServosRestsWhereMujocosDoes) {
  const test::TempFolder folder("linx_mjcf_servo_arm");
  const fs::path path = folder.write("arm.xml", R"(<mujoco>
  <option timestep="0.001"/>
  <default><general gaintype="fixed" biastype="affine" gainprm="200" biasprm="0 -200 -20"/></default>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" axis="0 1 0" armature="0.01"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <body name="fore" pos="0.4 0 0">
        <joint name="elbow" axis="0 1 0" armature="0.01"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="hand" pos="0.3 0 0">
          <joint name="wrist" type="slide" axis="1 0 0"/>
          <geom type="box" size="0.05 0.03 0.02"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <general joint="shoulder"/>
    <general joint="elbow" gear="2" ctrllimited="true" ctrlrange="0.3 1" gainprm="100" biasprm="0 -100 -10"/>
    <general joint="wrist" gainprm="500" biasprm="0 -500 -50" ctrllimited="true"
             ctrlrange="-0.1 -0.05"/>
  </actuator>
</mujoco>)");
  MujocoModel mj(path);
  const Scene scene = importMjcf(path);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  World world = buildWorld(scene);
  for (int i = 0; i < 2000; ++i) {
    world.step();
    mj_step(mj.model, mj.data);
  }
  for (const char* name : {"upper", "fore", "hand"}) {
    const int b = mj.body(name);
    const Vec3 at = world.body(*world.findBody(name)).position();
    const Vec3 sag = at - Vec3(scene.bodies[static_cast<std::size_t>(b - 1)].position);
    std::printf("%s: %.2e m from MuJoCo's after 2 s (moved %.3f m from the start)\n", name,
                (at - mj.centre(b)).norm(), sag.norm());
    EXPECT_LT((at - mj.centre(b)).norm(), 1e-9) << name;
  }
  // The elbow at its target, 0.3 / 2 rad, less its sag: it has turned from its start.
  const double elbow =
      mj.data->qpos[mj.model->jnt_qposadr[mj_name2id(mj.model, mjOBJ_JOINT, "elbow")]];
  EXPECT_GT(elbow, 0.1);
}

// Mesh files of our own: an L-shaped prism (not convex: MuJoCo's legacy rule takes each pyramid's
// volume positive, which is not the solid's volume) as OBJ quads, and a tetrahedron as binary STL.
const char* kEllObj = R"(v 0 0 0
v 2 0 0
v 2 1 0
v 1 1 0
v 1 3 0
v 0 3 0
v 0 0 0.5
v 2 0 0.5
v 2 1 0.5
v 1 1 0.5
v 1 3 0.5
v 0 3 0.5
f 1 3 2
f 1 4 3
f 1 6 4
f 4 6 5
f 7 8 9
f 7 9 10
f 7 10 12
f 10 11 12
f 1 2 8 7
f 2 3 9 8
f 3 4 10 9
f 4 5 11 10
f 5 6 12 11
f 6 1 7 12
)";

// A binary STL of the triangles (each three corners).
std::string binaryStl(const std::vector<std::array<Vec3, 3>>& triangles) {
  std::string out(80, ' ');
  const auto put = [&](const void* p, std::size_t n) {
    out.append(static_cast<const char*>(p), n);
  };
  const auto count = static_cast<std::uint32_t>(triangles.size());
  put(&count, 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    put(normal, sizeof(normal));
    for (const Vec3& v : t) {
      const float corner[3] = {static_cast<float>(v.x()), static_cast<float>(v.y()),
                               static_cast<float>(v.z())};
      put(corner, sizeof(corner));
    }
    const std::uint16_t attributes = 0;
    put(&attributes, 2);
  }
  return out;
}

std::string tetrahedronStl() {
  const Vec3 a(0, 0, 0), b(0.3, 0.05, 0), c(0.1, 0.25, 0.02), d(0.07, 0.09, 0.2);
  return binaryStl({{a, c, b}, {a, b, d}, {b, c, d}, {c, a, d}});
}

// Mesh geoms: each body's mass, centre and inertia as MuJoCo computes them from its meshes (the
// legacy rule and exactmeshinertia), with scale, a mass given, a visual mesh that weighs, and a
// mesh beside a box. Both engines read the same float vertices and do the same arithmetic: a body
// of one mesh has the same mass, centre and principal moments to rounding. MuJoCo's principal
// axes are not as close: its Jacobi iteration (mju_eig3) stops at a turn whose cosine is within
// 1e-12 of 1 (a turn of up to 1.4e-6 rad) or an off-diagonal below 1e-12 (4.6e-7 relative on the
// tetrahedron here), where linx keeps the exact inertia; so the inertias as matrices agree to 3e-6,
// and a body of several parts, whose moments MuJoCo sums along those axes, to 1e-7 in its moments.
// The legacy mass, from the moments, agrees to MuJoCo's eigenvalues' 1e-11.
class MeshMasses : public ::testing::TestWithParam<bool> {};

TEST_P(MeshMasses, AreMujocos) {
  const test::TempFolder folder("linx_mjcf_mesh_mass");
  folder.write("meshes/ell.obj", kEllObj);
  folder.write("meshes/tet.stl", tetrahedronStl());
  const fs::path path = folder.write("meshes.xml", fmt::format(R"(<mujoco>
  <compiler meshdir="meshes" exactmeshinertia="{}"/>
  <asset>
    <mesh name="ell" file="ell.obj" scale="0.1 0.1 0.1"/>
    <mesh file="tet.stl" scale="1 2 0.5"/>
  </asset>
  <worldbody>
    <body name="a" pos="0 0 1" euler="10 20 30">
      <freejoint/>
      <geom type="mesh" mesh="ell" pos="0.1 0 0" euler="0 40 10" density="700"/>
      <body name="b" pos="0.5 0 0">
        <joint type="hinge" axis="0 1 0"/>
        <geom type="mesh" mesh="tet" mass="0.3"/>
      </body>
      <body name="c" pos="0 0.5 0">
        <joint type="hinge"/>
        <geom type="mesh" mesh="tet" quat="0.9 0.1 0.3 0.2"/>
        <geom type="box" size="0.1 0.05 0.02" pos="0 0.1 0"/>
        <geom type="mesh" mesh="ell" contype="0" conaffinity="0" euler="30 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>)",
                                                               GetParam() ? "true" : "false"));
  MujocoModel mj(path);
  const Scene scene = importMjcf(path);
  World world = buildWorld(scene);
  for (const auto& [name, moments_tolerance] : {std::pair{"a", 1e-9}, {"b", 1e-9}, {"c", 1e-7}}) {
    SCOPED_TRACE(name);
    const int b = mj.body(name);
    const Body& body = world.body(*world.findBody(name));
    const double moments_error = momentsError(body, mj, b);
    const double inertia_error =
        (body.inertiaWorld() - mj.inertia(b)).norm() / mj.inertia(b).norm();
    std::printf(
        "%s: mass %.17g kg (MuJoCo %.17g), centre %.2e m, principal moments %.2e, inertia "
        "%.2e (relative)\n",
        name, body.mass(), mj.model->body_mass[b], (body.position() - mj.centre(b)).norm(),
        moments_error, inertia_error);
    EXPECT_NEAR(body.mass() / mj.model->body_mass[b], 1.0, 1e-11);
    EXPECT_LT((body.position() - mj.centre(b)).norm(), 1e-12);
    EXPECT_LT(moments_error, moments_tolerance);
    EXPECT_LT(inertia_error, 3e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(MjcfAgainstMujoco, MeshMasses, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Exact" : "Legacy"; });

// MuJoCo's mug sample: a visual mesh (a non-convex cup, weighed by the legacy rule) among 40 boxes,
// on one body. Its mass to MuJoCo's eigenvalues' accuracy, its principal moments to that of its
// axes (see MeshMasses).
TEST(MjcfAgainstMujoco, MugMassIsMujocos) {
  const fs::path mug = "/usr/share/mujoco/model/mug/mug.xml";
  if (!fs::exists(mug)) GTEST_SKIP() << mug << " is missing (Debian's libmujoco-samples)";
  MujocoModel mj(mug);
  const Scene scene = importMjcf(mug);
  World world = buildWorld(scene);
  const int b = mj.body("mug");
  ASSERT_GE(b, 0);
  const Body& body = world.body(*world.findBody("mug"));
  const double moments_error = momentsError(body, mj, b);
  std::printf("mug: %.17g kg (MuJoCo %.17g), centre %.2e m, principal moments %.2e (relative)\n",
              body.mass(), mj.model->body_mass[b], (body.position() - mj.centre(b)).norm(),
              moments_error);
  EXPECT_NEAR(body.mass() / mj.model->body_mass[b], 1.0, 1e-11);
  EXPECT_LT((body.position() - mj.centre(b)).norm(), 1e-12);
  EXPECT_LT(moments_error, 1e-7);
}

TEST(MjcfAgainstMujoco, HumanoidFallsAndLiesDownWithItsJointsHeld) {
  if (!fs::exists(kHumanoid))
    GTEST_SKIP() << kHumanoid << " is missing (Debian's libmujoco-samples)";
  const Scene scene = importMjcf(kHumanoid);
  World world = buildWorld(scene);
  const BodyId torso = *world.findBody("torso");
  // A joint's error is its equality rows' or a limit's overshoot: the limbs hit their limits as
  // it lands (MuJoCo's limits here are soft, solimplimit="0 .99 .01"); what is not overshoot must
  // be the equality rows', held to round-off.
  double overshoot = 0.0, unexplained = 0.0;
  for (int i = 0; i < 600; ++i) {  // 3 s at the file's 5 ms
    world.step();
    for (int j = 0; j < world.jointCount(); ++j) {
      const JointId id{j};
      const JointCoordinates q = world.jointCoordinates(id);
      double over = 0.0;
      for (int c = 0; c < world.joint(id).freeCoordinates(); ++c) {
        const auto& limits = world.joint(id).def().coordinates[static_cast<std::size_t>(c)].limits;
        if (limits) over = std::max({over, limits->lower - q[c], q[c] - limits->upper});
      }
      overshoot = std::max(overshoot, over);
      unexplained = std::max(unexplained, world.jointError(id) - over);
    }
  }
  const Body& t = world.body(torso);
  std::printf(
      "3 s: torso at height %.3f m, speed %.3f m/s; largest limit overshoot %.2e rad, "
      "other joint error %.2e\n",
      t.position().z(), t.linearVelocity().norm(), overshoot, unexplained);
  // Lying on the floor: the torso's centre within a body's thickness or two of it.
  EXPECT_LT(t.position().z(), 0.4);
  EXPECT_GT(t.position().z(), 0.05);
  EXPECT_LT(overshoot, 0.05);
  EXPECT_LT(unexplained, 1e-9);
}

}  // namespace
}  // namespace linx
