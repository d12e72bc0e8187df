// The typed joint definitions (linx/joint_defs.hpp) make the same joints as the JointDefs written
// out by hand: each type, with a limit, spring or drive on a chosen coordinate so that a field put
// in the wrong place shows, moves to the bit as the hand-written joint over a second of tumbling.
// (The joints themselves are validated against closed forms in their own tests.)
#include "support.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace linx {
namespace {

// Two boxes side by side, spinning and drifting, without gravity's bias to one direction.
std::pair<BodyId, BodyId> twoBoxes(World& world) {
  BodyDef a = test::boxBody("a", 1.0, Vec3(0.4, 0.2, 0.1), Vec3(0, 0, 1));
  a.angular_velocity = Vec3(1.0, -2.0, 3.0);
  a.linear_velocity = Vec3(0.3, 0.1, -0.2);
  BodyDef b = test::boxBody("b", 2.0, Vec3(0.3, 0.3, 0.3), Vec3(0.6, 0.1, 1.1));
  b.angular_velocity = Vec3(-0.5, 1.0, 0.2);
  return {world.createBody(a), world.createBody(b)};
}

// Steps the typed and the hand-written joint's worlds and compares them to the bit.
void expectSameMotion(const std::function<JointId(World&, BodyId, BodyId)>& typed,
                      const std::function<JointId(World&, BodyId, BodyId)>& by_hand) {
  World x, y;
  const auto [a1, b1] = twoBoxes(x);
  const auto [a2, b2] = twoBoxes(y);
  const JointId jx = typed(x, a1, b1), jy = by_hand(y, a2, b2);
  EXPECT_EQ(x.joint(jx).type(), y.joint(jy).type());
  for (int n = 0; n < 1000; ++n) {
    x.step();
    y.step();
  }
  for (const BodyId id : {a1, b1}) {
    EXPECT_EQ(x.body(id).position(), y.body(id).position()) << x.body(id).name();
    EXPECT_EQ(x.body(id).angularVelocity(), y.body(id).angularVelocity()) << x.body(id).name();
  }
  EXPECT_EQ(x.jointCoordinates(jx), y.jointCoordinates(jy));
  EXPECT_TRUE(x.body(a1).position() != Vec3(0, 0, 1));  // it moved
}

const Vec3 kAnchor(0.3, 0.05, 1.05);
CoordinateDef limited(double bound) {
  return CoordinateDef{.limits = JointLimits{-bound, bound}};
}
CoordinateDef sprung(double k) {
  return CoordinateDef{.spring = JointSpring{.stiffness = k}};
}

TEST(JointDefs, FixedSliderHingeBall) {
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(FixedDef{.name = "j", .body1 = a, .body2 = b, .anchor = kAnchor});
      },
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint("fixed",
                             JointDef{.name = "j", .body1 = a, .body2 = b, .anchor = kAnchor});
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(SliderDef{
            .name = "j", .body1 = a, .body2 = b, .axis = Vec3(1, 1, 0), .position = limited(0.02)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j", .body1 = a, .body2 = b, .axis = Vec3(1, 1, 0)};
        d.coordinates[0] = limited(0.02);
        return w.createJoint("slider", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(HingeDef{.name = "j",
                                      .body1 = a,
                                      .body2 = b,
                                      .local = true,
                                      .anchor = Vec3(0.2, 0, 0),
                                      .axis = Vec3(0, 1, 1),
                                      .angle = sprung(3.0)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .local = true,
                   .anchor = Vec3(0.2, 0, 0),
                   .axis = Vec3(0, 1, 1)};
        d.coordinates[0] = sprung(3.0);
        return w.createJoint("hinge", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(BallDef{.name = "j", .body1 = a, .body2 = b, .anchor = kAnchor});
      },
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint("ball",
                             JointDef{.name = "j", .body1 = a, .body2 = b, .anchor = kAnchor});
      });
}

TEST(JointDefs, TwoAndThreeCoordinateTypes) {
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(UniversalDef{.name = "j",
                                          .body1 = a,
                                          .body2 = b,
                                          .anchor = kAnchor,
                                          .axis1 = Vec3::UnitX(),
                                          .axis2 = Vec3::UnitZ(),
                                          .angle2 = limited(0.1)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .anchor = kAnchor,
                   .axis = Vec3::UnitX(),
                   .axis2 = Vec3::UnitZ()};
        d.coordinates[1] = limited(0.1);
        return w.createJoint("universal", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(CylindricalDef{.name = "j",
                                            .body1 = a,
                                            .body2 = b,
                                            .anchor = kAnchor,
                                            .axis = Vec3::UnitX(),
                                            .position = sprung(50.0),
                                            .angle = limited(0.2)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j", .body1 = a, .body2 = b, .anchor = kAnchor, .axis = Vec3::UnitX()};
        d.coordinates[0] = sprung(50.0);
        d.coordinates[1] = limited(0.2);
        return w.createJoint("cylindrical", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(Hinge2Def{.name = "j",
                                       .body1 = a,
                                       .body2 = b,
                                       .anchor = kAnchor,
                                       .axis1 = Vec3::UnitY(),
                                       .axis2 = Vec3::UnitZ(),
                                       .steering = limited(0.1),
                                       .suspension = sprung(100.0)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .anchor = kAnchor,
                   .axis = Vec3::UnitY(),
                   .axis2 = Vec3::UnitZ()};
        d.coordinates[1] = limited(0.1);
        d.coordinates[2] = sprung(100.0);
        return w.createJoint("hinge2", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(PlanarDef{.name = "j",
                                       .body1 = a,
                                       .body2 = b,
                                       .anchor = kAnchor,
                                       .axis1 = Vec3::UnitX(),
                                       .axis2 = Vec3::UnitY(),
                                       .y = limited(0.01),
                                       .angle = sprung(2.0)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .anchor = kAnchor,
                   .axis = Vec3::UnitX(),
                   .axis2 = Vec3::UnitY()};
        d.coordinates[1] = limited(0.01);
        d.coordinates[2] = sprung(2.0);
        return w.createJoint("planar", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(ConeTwistDef{.name = "j",
                                          .body1 = a,
                                          .body2 = b,
                                          .anchor = kAnchor,
                                          .axis1 = Vec3::UnitX(),
                                          .axis2 = Vec3::UnitY(),
                                          .cone = ConeLimit{0.3, 0.2},
                                          .twist = limited(0.2)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .anchor = kAnchor,
                   .axis = Vec3::UnitX(),
                   .axis2 = Vec3::UnitY(),
                   .cone = ConeLimit{0.3, 0.2}};
        d.coordinates[0] = limited(0.2);
        return w.createJoint("cone_twist", d);
      });
}

TEST(JointDefs, GenericDistanceSpringGearRackSerial) {
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(GenericDef{.name = "j",
                                        .body1 = a,
                                        .body2 = b,
                                        .anchor = kAnchor,
                                        .axis1 = Vec3::UnitX(),
                                        .axis2 = Vec3::UnitY(),
                                        .y = CoordinateDef{.locked = true},
                                        .rz = sprung(4.0)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .anchor = kAnchor,
                   .axis = Vec3::UnitX(),
                   .axis2 = Vec3::UnitY()};
        d.coordinates[1] = CoordinateDef{.locked = true};
        d.coordinates[5] = sprung(4.0);
        return w.createJoint("generic", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(DistanceDef{.name = "j",
                                         .body1 = a,
                                         .body2 = b,
                                         .anchor1 = Vec3(0.2, 0, 1),
                                         .length = 0.5,
                                         .rope = true});
      },
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint("distance", JointDef{.name = "j",
                                                  .body1 = a,
                                                  .body2 = b,
                                                  .anchor = Vec3(0.2, 0, 1),
                                                  .length = 0.5,
                                                  .rope = true});
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(SpringDef{.name = "j",
                                       .body1 = a,
                                       .body2 = b,
                                       .anchor2 = Vec3(0.5, 0.1, 1.1),
                                       .length = sprung(30.0)});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j", .body1 = a, .body2 = b, .anchor2 = Vec3(0.5, 0.1, 1.1)};
        d.coordinates[0] = sprung(30.0);
        return w.createJoint("spring", d);
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(GearDef{.name = "j",
                                     .body1 = a,
                                     .body2 = b,
                                     .axis1 = Vec3::UnitZ(),
                                     .axis2 = Vec3::UnitY(),
                                     .ratio = -2.0});
      },
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint("gear", JointDef{.name = "j",
                                              .body1 = a,
                                              .body2 = b,
                                              .axis = Vec3::UnitZ(),
                                              .axis2 = Vec3::UnitY(),
                                              .ratio = -2.0});
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(RackAndPinionDef{.name = "j",
                                              .body1 = a,
                                              .body2 = b,
                                              .axis1 = Vec3::UnitZ(),
                                              .axis2 = Vec3::UnitX(),
                                              .ratio = 0.1});
      },
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint("rack_and_pinion", JointDef{.name = "j",
                                                         .body1 = a,
                                                         .body2 = b,
                                                         .axis = Vec3::UnitZ(),
                                                         .axis2 = Vec3::UnitX(),
                                                         .ratio = 0.1});
      });
  expectSameMotion(
      [](World& w, BodyId a, BodyId b) {
        return w.createJoint(SerialDef{
            .name = "j",
            .body1 = a,
            .body2 = b,
            .axes = {{.axis = Vec3::UnitX(), .anchor = kAnchor, .coordinate = sprung(1.0)},
                     {.linear = true, .axis = Vec3::UnitY(), .coordinate = limited(0.05)}}});
      },
      [](World& w, BodyId a, BodyId b) {
        JointDef d{.name = "j",
                   .body1 = a,
                   .body2 = b,
                   .axes = {{false, Vec3::UnitX(), kAnchor}, {true, Vec3::UnitY(), Vec3::Zero()}}};
        d.coordinates[0] = sprung(1.0);
        d.coordinates[1] = limited(0.05);
        return w.createJoint("serial", d);
      });
}

TEST(JointDefs, TypedDefinitionsAreCheckedAsJointDefsAre) {
  World world;
  const auto [a, b] = twoBoxes(world);
  EXPECT_THROW(world.createJoint(HingeDef{.name = "h", .body1 = a, .body2 = b}),
               std::invalid_argument);  // no anchor
  EXPECT_THROW(world.createJoint(UniversalDef{.name = "u",
                                              .body1 = a,
                                              .anchor = kAnchor,
                                              .axis1 = Vec3::UnitX(),
                                              .axis2 = Vec3::UnitX()}),
               std::invalid_argument);  // axes not perpendicular
  EXPECT_THROW(world.createJoint(SerialDef{.name = "s", .body1 = a}), std::invalid_argument);
}

}  // namespace
}  // namespace linx
