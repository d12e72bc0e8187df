// Mimic joints: one joint's coordinate held at a ratio of another's plus an offset (URDF's
// <mimic>). Each test drives the leader with a constant force F along its coordinate in zero
// gravity and compares with the closed form of the coupled system: q'' = F / m_eff, m_eff the
// inertia of everything that moves with q, as the Lagrangian of the coupled system gives it.
#include <linx/import.hpp>
#include <linx/scene.hpp>
#include <linx/world.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "support.hpp"

using namespace linx;

namespace {

WorldSettings settings(SolverType type) {
  WorldSettings s;
  s.timestep = 1e-3;
  s.sleep.enabled = false;
  s.gravity.setZero();
  s.solver.type = type;
  if (type == SolverType::Pgs) {
    s.solver.iterations = 200;
    s.solver.tolerance = 1e-12;
  }
  return s;
}

JointDef slider(const char* name, BodyId body1, BodyId body2, const Vec3& axis) {
  JointDef d;
  d.name = name;
  d.body1 = body1;
  d.body2 = body2;
  d.axis = axis;
  return d;
}

JointDef mimic(const char* name, JointId leader, JointId follower, double ratio, double offset) {
  JointDef d;
  d.name = name;
  d.leader = leader;
  d.follower = follower;
  d.ratio = ratio;
  d.offset = offset;
  return d;
}

// The step's own error on a constant acceleration: semi-implicit Euler is ahead by a h t / 2, h / t
// of the distance travelled (1e-3 at t = 1 s with h = 1 ms); the margin is half as much again.
constexpr double kEuler = 1.5e-3;

constexpr SolverType kSolvers[] = {SolverType::Soft, SolverType::Exact, SolverType::Pgs,
                                   SolverType::Auto};

}  // namespace

TEST(Mimic, WheelsOnFixedAxlesTurnAtTheRatioWithTheirJointInertia) {
  // Two discs on hinges to the world about z; the follower turns at r times the leader. A torque
  // tau on the leader's angle: q'' = tau / (I1 + r^2 I2), the follower at r q + offset. The offset
  // holds from the start: the follower's hinge has its reference there.
  for (const SolverType type : kSolvers) {
    const std::string name(solverTypeName(type));
    World world(settings(type));
    const double r = -2.5, tau = 0.3, offset = 0.2;
    const BodyId a = world.createBody(test::boxBody("a", 2.0, Vec3(0.4, 0.4, 0.1), Vec3::Zero()));
    const BodyId b =
        world.createBody(test::boxBody("b", 0.5, Vec3(0.2, 0.2, 0.1), Vec3(0.5, 0, 0)));
    JointDef h1;
    h1.name = "leader";
    h1.body1 = a;
    h1.anchor = Vec3::Zero();
    h1.axis = Vec3::UnitZ();
    h1.coordinates[0].force = Signal(tau);
    JointDef h2 = h1;
    h2.name = "follower";
    h2.body1 = b;
    h2.anchor = Vec3(0.5, 0, 0);
    h2.coordinates[0] = CoordinateDef{};
    h2.coordinates[0].reference = offset;  // built where the mimic wants it at q = 0
    const JointId leader = world.createJoint("hinge", h1);
    const JointId follower = world.createJoint("hinge", h2);
    world.createJoint("mimic", mimic("tie", leader, follower, r, offset));
    const double i1 = world.body(a).inertiaWorld()(2, 2), i2 = world.body(b).inertiaWorld()(2, 2);
    const double acc = tau / (i1 + r * r * i2);
    double worst = 0.0, worst_tie = 0.0;
    for (int n = 1; n <= 1500; ++n) {
      world.step();
      const double t = world.time();
      const double q = world.jointCoordinates(leader)[0];
      worst = std::max(worst, std::abs(q - 0.5 * acc * t * t));
      worst_tie =
          std::max(worst_tie, std::abs(world.jointCoordinates(follower)[0] - (r * q + offset)));
    }
    std::printf(
        "%s: leader within %.2e rad of tau t^2 / 2 (I1 + r^2 I2) (%.4f rad), follower "
        "within %.2e rad of r q + offset\n",
        name.c_str(), worst, world.jointCoordinates(leader)[0], worst_tie);
    EXPECT_LT(worst, kEuler * world.jointCoordinates(leader)[0]) << name;
    EXPECT_LT(worst_tie, 1e-6) << name;
    EXPECT_GT(std::abs(world.jointCoordinates(follower)[0]), M_PI) << "past half a turn: counted";
  }
}

TEST(Mimic, FingersOnAFloatingPalmMoveItAsTheLagrangianSays) {
  // A free palm (mass M) with two fingers (mass m each) on sliders along x, the second following
  // the first (ratio 1): three bodies in one row. A force F on the first finger's slide. Momentum
  // stays zero, so the palm moves back by X = -2 m q / (M + 2 m), and q'' = F / mu with
  // mu = 2 m M / (M + 2 m). With ratio -1 the fingers close symmetrically and the palm stays.
  for (const SolverType type : kSolvers) {
    const std::string name(solverTypeName(type));
    for (const double ratio : {1.0, -1.0}) {
      World world(settings(type));
      const double big = 3.0, m = 0.5, force = 2.0;
      const BodyId palm =
          world.createBody(test::boxBody("palm", big, Vec3(0.3, 0.1, 0.1), Vec3::Zero()));
      const BodyId f1 =
          world.createBody(test::boxBody("f1", m, Vec3(0.05, 0.05, 0.2), Vec3(0.1, 0, 0)));
      const BodyId f2 =
          world.createBody(test::boxBody("f2", m, Vec3(0.05, 0.05, 0.2), Vec3(-0.1, 0, 0)));
      JointDef s1 = slider("s1", f1, palm, Vec3::UnitX());
      s1.coordinates[0].force = Signal(force);
      const JointId j1 = world.createJoint("slider", s1);
      const JointId j2 = world.createJoint("slider", slider("s2", f2, palm, Vec3::UnitX()));
      world.createJoint("mimic", mimic("tie", j1, j2, ratio, 0.0));
      const double mu = ratio > 0 ? 2 * m * big / (big + 2 * m) : 2 * m;
      double worst = 0.0, worst_palm = 0.0, worst_tie = 0.0;
      for (int n = 1; n <= 1000; ++n) {
        world.step();
        const double t = world.time(), q = world.jointCoordinates(j1)[0];
        const double palm_x = ratio > 0 ? -2 * m * q / (big + 2 * m) : 0.0;
        worst = std::max(worst, std::abs(q - 0.5 * force / mu * t * t));
        worst_palm = std::max(worst_palm, std::abs(world.body(palm).position().x() - palm_x));
        worst_tie = std::max(worst_tie, std::abs(world.jointCoordinates(j2)[0] - ratio * q));
      }
      const double q = world.jointCoordinates(j1)[0];
      std::printf(
          "%s, ratio %+.0f: finger within %.2e m of F t^2 / 2 mu (%.4f m), palm within "
          "%.2e m, follower within %.2e m\n",
          name.c_str(), ratio, worst, q, worst_palm, worst_tie);
      EXPECT_LT(worst, kEuler * q) << name;
      EXPECT_LT(worst_palm, kEuler * q) << name;
      EXPECT_LT(worst_tie, 1e-6) << name;
    }
  }
}

TEST(Mimic, JointsOnSeparatePairsOfBodiesShareTheLeadersForce) {
  // Four bodies: pair 1 (M1, m1) on a slider, pair 2 (M2, m2) on another, all floating, the
  // second slide at r times the first, each along the line through its two bodies' centres (else
  // the pair turns as the slide moves its mass off the line). Each pair keeps its momentum; its
  // slide's inertia is the reduced mass mu_i = M_i m_i / (M_i + m_i), so q1'' = F / (mu1 + r^2
  // mu2).
  for (const SolverType type : kSolvers) {
    const std::string name(solverTypeName(type));
    World world(settings(type));
    const double r = 0.5, force = 1.0;
    const BodyId p1 = world.createBody(test::boxBody("p1", 2.0, Vec3(0.2, 0.2, 0.2), Vec3::Zero()));
    const BodyId c1 =
        world.createBody(test::boxBody("c1", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0.3, 0)));
    const BodyId p2 =
        world.createBody(test::boxBody("p2", 4.0, Vec3(0.2, 0.2, 0.2), Vec3(1, 0, 0)));
    const BodyId c2 =
        world.createBody(test::boxBody("c2", 0.5, Vec3(0.1, 0.1, 0.1), Vec3(1.2, 0.2, 0)));
    JointDef s1 = slider("s1", c1, p1, Vec3::UnitY());
    s1.coordinates[0].force = Signal(force);
    const JointId j1 = world.createJoint("slider", s1);
    const JointId j2 = world.createJoint("slider", slider("s2", c2, p2, Vec3(1, 1, 0)));
    world.createJoint("mimic", mimic("tie", j1, j2, r, 0.0));
    const double mu1 = 2.0 * 1.0 / 3.0, mu2 = 4.0 * 0.5 / 4.5;
    const double acc = force / (mu1 + r * r * mu2);
    double worst = 0.0, worst_tie = 0.0, worst_momentum = 0.0;
    for (int n = 1; n <= 1000; ++n) {
      world.step();
      const double t = world.time(), q = world.jointCoordinates(j1)[0];
      worst = std::max(worst, std::abs(q - 0.5 * acc * t * t));
      worst_tie = std::max(worst_tie, std::abs(world.jointCoordinates(j2)[0] - r * q));
      for (const auto& [p, c] : {std::pair{p1, c1}, std::pair{p2, c2}}) {
        const Vec3 momentum = world.body(p).mass() * world.body(p).linearVelocity() +
                              world.body(c).mass() * world.body(c).linearVelocity();
        worst_momentum = std::max(worst_momentum, momentum.norm());
      }
    }
    const double q = world.jointCoordinates(j1)[0];
    std::printf(
        "%s: leader within %.2e m of F t^2 / 2 (mu1 + r^2 mu2) (%.4f m), follower within "
        "%.2e m, each pair's momentum below %.2e kg m/s\n",
        name.c_str(), worst, q, worst_tie, worst_momentum);
    EXPECT_LT(worst, kEuler * q) << name;
    EXPECT_LT(worst_tie, 1e-6) << name;
    EXPECT_LT(worst_momentum, 1e-9) << name;
  }
}

TEST(Mimic, GoesWithTheJointsItTies) {
  World world(settings(SolverType::Soft));
  const BodyId a = world.createBody(test::boxBody("a", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(1, 0, 0)));
  const JointId j1 = world.createJoint("slider", slider("s1", a, kWorldBody, Vec3::UnitX()));
  const JointId j2 = world.createJoint("slider", slider("s2", b, kWorldBody, Vec3::UnitX()));
  const JointId tie =
      world.createJoint(MimicDef{.name = "tie", .leader = j1, .follower = j2, .ratio = 1.0});
  EXPECT_EQ(world.joint(tie).body1(), b);  // the follower's bodies
  world.removeJoint(j1);
  EXPECT_FALSE(world.contains(tie));
  EXPECT_TRUE(world.contains(j2));
  world.step();  // b slides freely: nothing left refers to the removed joint
  EXPECT_THROW(world.createJoint("mimic", mimic("tie", j2, j2, 1.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(world.createJoint("mimic", mimic("tie", j1, j2, 1.0, 0.0)), std::invalid_argument);
  JointDef ball;
  ball.name = "ball";
  ball.body1 = a;
  ball.anchor = Vec3::Zero();
  const JointId bj = world.createJoint("ball", ball);
  try {
    world.createJoint("mimic", mimic("tie2", bj, j2, 1.0, 0.0));
    FAIL() << "a ball joint has no coordinate row";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("leader: joint 'ball' is a ball joint"), std::string::npos)
        << e.what();
  }
}

TEST(Mimic, UrdfGripperKeepsItsFingersTogetherOnAMovingArm) {
  // A gripper on a hinge (gravity swings it), two prismatic fingers on mirrored axes, the second
  // mimicking the first with multiplier -1 and an offset (so they slide together as the palm
  // swings): read from URDF, run, the coupling holds. At the zero pose the offset is not yet
  // met: the first step closes it.
  const auto dir = std::filesystem::temp_directory_path() / "linx_urdf_gripper";
  std::filesystem::create_directories(dir);
  const auto path = dir / "gripper.urdf";
  std::ofstream(path) << R"(<robot name="gripper">
  <link name="base"/>
  <link name="palm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="left"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="right"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="swing" type="continuous"><parent link="base"/><child link="palm"/>
    <origin xyz="0 0 1"/><axis xyz="0 1 0"/></joint>
  <joint name="left_finger" type="prismatic"><parent link="palm"/><child link="left"/>
    <origin xyz="0.05 0 -0.3"/><axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
  <joint name="right_finger" type="prismatic"><parent link="palm"/><child link="right"/>
    <origin xyz="-0.05 0 -0.3"/><axis xyz="-1 0 0"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/>
    <mimic joint="left_finger" multiplier="-1" offset="0.01"/></joint>
</robot>)";
  Scene scene = importUrdf(path);
  for (const std::string& w : scene.warnings) EXPECT_EQ(w.find("mimic"), std::string::npos) << w;
  ASSERT_EQ(scene.joints.back().type, "mimic");
  World world = buildWorld(scene);
  const JointId swing = world.findJoint("swing").value(),
                left = world.findJoint("left_finger").value(),
                right = world.findJoint("right_finger").value();
  world.body(world.joint(swing).body1()).setAngularVelocity(Vec3(0, 3.0, 0));
  double worst = 0.0, travel = 0.0;
  for (int n = 0; n < 1000; ++n) {
    world.step();
    const double q = world.jointCoordinates(left)[0];
    travel = std::max(travel, std::abs(q));
    if (n > 0) worst = std::max(worst, std::abs(world.jointCoordinates(right)[0] - (-q + 0.01)));
  }
  std::printf("fingers travelled up to %.4f m; right within %.2e m of 0.01 - left\n", travel,
              worst);
  EXPECT_GT(travel, 0.01);
  EXPECT_LT(worst, 1e-6);
  std::filesystem::remove_all(dir);
}

TEST(Mimic, SceneFilesNameTheJointsItTies) {
  const std::string text = R"({
    "gravity": [0, 0, 0],
    "bodies": [{"name": "a", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": [0, 0, 0]},
               {"name": "b", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": [1, 0, 0],
                "angular_velocity": [0, 0, 1]}],
    "joints": [{"name": "h1", "type": "hinge", "body1": "a", "anchor": [0, 0, 0], "axis": [0, 0, 1]},
               {"name": "h2", "type": "hinge", "body1": "b", "anchor": [1, 0, 0], "axis": [0, 0, 1]},
               {"name": "tie", "type": "mimic", "leader": "h1", "follower": "h2", "ratio": -3,
                "offset": 0}]})";
  const Scene scene = parseScene(text, "m.json");
  ASSERT_EQ(scene.joints.size(), 3u);
  EXPECT_EQ(scene.joints[2].def.leader, JointId{0});
  // Written back the same (`linx convert` of a URDF with <mimic>).
  const Scene again = parseScene(writeSceneJson(scene), "again.json");
  EXPECT_EQ(again.joints[2].def.follower, JointId{1});
  EXPECT_EQ(again.joints[2].def.ratio, -3.0);
  // b spun at 1 rad/s, a at rest: the tie shares the momentum about the axles,
  // I w0 = I (w1 + r w2) with w2 = r w1 (equal discs): w1 = r w0 / (1 + r^2).
  World world = buildWorld(again);
  world.step();
  const double r = -3.0, w1 = r * 1.0 / (1 + r * r);
  EXPECT_NEAR(world.body(BodyId{0}).angularVelocity().z(), w1, 1e-9);
  EXPECT_NEAR(world.body(BodyId{1}).angularVelocity().z(), r * w1, 1e-9);

  const auto refused = [&](const std::string& bad, const std::string& where,
                           const std::string& problem) {
    try {
      parseScene(bad, "bad.json");
      ADD_FAILURE() << "accepted; expected " << problem;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), where) << e.what();
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  };
  std::string later = text;
  later.replace(later.find("\"leader\": \"h1\""), 14, "\"leader\": \"tie\"");
  refused(later, "joints[2].leader", "no joint 'tie' before this mimic joint");
  std::string bodies = text;
  bodies.replace(bodies.find("\"leader\""), 0, "\"body1\": \"a\", ");
  refused(bodies, "joints[2].body1", "not used by a mimic joint");
}
