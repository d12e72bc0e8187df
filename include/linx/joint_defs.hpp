// A definition per joint type, with only the fields that type takes: World::createJoint(HingeDef{
// .name = "pivot", .body1 = rod, .anchor = ..., .axis = ..., .angle = {.limits = ...}}). Each is
// the typed form of a JointDef (toJointDef), whose fields say what each one means; the common
// ones come first in every struct, in the same order. A coordinate's fields are named as the type
// names its coordinates (JointTypeInfo::coordinates, the scene format's names).
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/types.hpp>

#include <concepts>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace linx {

// The fields every type has (JointDef's meaning), written once: first name, body1, body2, local,
// then the type's own fields, then break_force, break_torque, erp, cfm, collide (a mimic joint
// has no bodies: its are the follower's).
#define LINX_JOINT_HEAD      \
  std::string name;          \
  BodyId body1 = kWorldBody; \
  BodyId body2 = kWorldBody; \
  bool local = false;
#define LINX_JOINT_TAIL                                                          \
  std::optional<double> break_force = std::nullopt, break_torque = std::nullopt; \
  std::optional<double> erp = std::nullopt, cfm = std::nullopt;                  \
  bool collide = false;

/// Glues body1 to body2 (or the world) as they are at creation.
struct FixedDef {
  static constexpr std::string_view kType = "fixed";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< where the reaction torque is taken
  LINX_JOINT_TAIL
};

/// Translation along `axis` only.
struct SliderDef {
  static constexpr std::string_view kType = "slider";
  LINX_JOINT_HEAD
  Vec3 axis = Vec3::UnitZ();
  CoordinateDef position = {};
  LINX_JOINT_TAIL
};

/// Rotation about `axis` through `anchor` only.
struct HingeDef {
  static constexpr std::string_view kType = "hinge";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis = Vec3::UnitZ();
  CoordinateDef angle = {};
  LINX_JOINT_TAIL
};

/// Rotation about `anchor` only; `angle`, the angle of the relative rotation, takes an upper
/// limit (in [0, pi)), which keeps the rotation within a cone about its start.
struct BallDef {
  static constexpr std::string_view kType = "ball";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  CoordinateDef angle = {};                   ///< limits only
  LINX_JOINT_TAIL
};

/// A Cardan cross at `anchor`: `axis1` turns with body 1, `axis2` with body 2.
struct UniversalDef {
  static constexpr std::string_view kType = "universal";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis1 = Vec3::UnitZ();
  Vec3 axis2 = Vec3::UnitY();  ///< perpendicular to axis1 at creation
  CoordinateDef angle1 = {}, angle2 = {};
  LINX_JOINT_TAIL
};

/// Translation along and rotation about `axis` through `anchor` (a piston).
struct CylindricalDef {
  static constexpr std::string_view kType = "cylindrical";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis = Vec3::UnitZ();
  CoordinateDef position = {}, angle = {};
  LINX_JOINT_TAIL
};

/// A car's wheel (body 1) on its chassis (body 2): spinning about the axle `axis1`, steering about
/// and sprung along `axis2`.
struct Hinge2Def {
  static constexpr std::string_view kType = "hinge2";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required: the wheel's centre
  Vec3 axis1 = Vec3::UnitY();                 ///< the axle
  Vec3 axis2 = Vec3::UnitZ();                 ///< steering and suspension
  CoordinateDef wheel = {}, steering = {}, suspension = {};
  LINX_JOINT_TAIL
};

/// A massless rod (or a rope) between `anchor1` on body 1 and `anchor2` on body 2.
struct DistanceDef {
  static constexpr std::string_view kType = "distance";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor1 = std::nullopt;   ///< default body 1's centre
  std::optional<Vec3> anchor2 = std::nullopt;   ///< default body 2's centre; required for the world
  std::optional<double> length = std::nullopt;  ///< default the points' distance at creation
  bool rope = false;
  LINX_JOINT_TAIL
};

/// A ball joint whose twist axis `axis1` swings within an elliptical `cone`.
struct ConeTwistDef {
  static constexpr std::string_view kType = "cone_twist";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis1 = Vec3::UnitZ();                 ///< the twist axis
  Vec3 axis2 = Vec3::UnitY();                 ///< perpendicular: the direction of swing1
  std::optional<ConeLimit> cone = std::nullopt;
  CoordinateDef twist = {};
  LINX_JOINT_TAIL
};

/// Motion in the plane of `axis1` and `axis2` through `anchor`.
struct PlanarDef {
  static constexpr std::string_view kType = "planar";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis1 = Vec3::UnitX();
  Vec3 axis2 = Vec3::UnitY();  ///< perpendicular to axis1
  CoordinateDef x = {}, y = {}, angle = {};
  LINX_JOINT_TAIL
};

/// Body 2 turning about `axis2` at `ratio` times body 1's rate about `axis1`.
struct GearDef {
  static constexpr std::string_view kType = "gear";
  LINX_JOINT_HEAD
  Vec3 axis1 = Vec3::UnitZ();
  Vec3 axis2 = Vec3::UnitZ();
  double ratio = 1.0;  ///< non-zero; its sign is the sense
  LINX_JOINT_TAIL
};

/// Six axes, each locked, free, limited, driven or sprung: x, y, z along the joint's frame (axis1,
/// axis2, axis1 x axis2), rx, ry, rz its Cardan angles.
struct GenericDef {
  static constexpr std::string_view kType = "generic";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor = std::nullopt;  ///< required
  Vec3 axis1 = Vec3::UnitX();
  Vec3 axis2 = Vec3::UnitY();
  CoordinateDef x = {}, y = {}, z = {}, rx = {}, ry = {}, rz = {};
  LINX_JOINT_TAIL
};

/// Nothing held: the distance between `anchor1` and `anchor2` is a coordinate for what acts on it
/// (a spring, a linear actuator, a strut with stops).
struct SpringDef {
  static constexpr std::string_view kType = "spring";
  LINX_JOINT_HEAD
  std::optional<Vec3> anchor1 = std::nullopt;
  std::optional<Vec3> anchor2 = std::nullopt;
  CoordinateDef length = {};  ///< limits are the shortest and longest lengths, spring.rest one
  LINX_JOINT_TAIL
};

/// Body 2 (the rack) travelling along `axis2` by `ratio` (m/rad) times body 1's (the pinion's)
/// turn about `axis1`.
struct RackAndPinionDef {
  static constexpr std::string_view kType = "rack_and_pinion";
  LINX_JOINT_HEAD
  Vec3 axis1 = Vec3::UnitZ();
  Vec3 axis2 = Vec3::UnitX();
  double ratio = 1.0;  ///< the pitch radius (m/rad), non-zero
  LINX_JOINT_TAIL
};

/// One hinge or slide of a SerialDef with what acts on its coordinate.
struct SerialAxisDef {
  bool linear = false;         ///< a slide along `axis` (else a hinge about it)
  Vec3 axis = Vec3::UnitZ();   ///< non-zero direction
  Vec3 anchor = Vec3::Zero();  ///< a point on a hinge's axis
  CoordinateDef coordinate = {};
};

/// Hinges and slides in series (1 to 6), from body 2 to body 1 (JointDef::axes).
struct SerialDef {
  static constexpr std::string_view kType = "serial";
  LINX_JOINT_HEAD
  std::vector<SerialAxisDef> axes = {};
  LINX_JOINT_TAIL
};

/// Ties two joints (hinges or sliders): the follower's coordinate is held at ratio times the
/// leader's plus offset (URDF's <mimic>); the row acts on both joints' bodies.
struct MimicDef {
  static constexpr std::string_view kType = "mimic";
  std::string name;
  std::optional<JointId> leader = std::nullopt;    ///< required
  std::optional<JointId> follower = std::nullopt;  ///< required, another joint
  double ratio = 1.0;                              ///< non-zero
  double offset = 0.0;                             ///< (m or rad)
  std::optional<double> break_force = std::nullopt, break_torque = std::nullopt;
  std::optional<double> erp = std::nullopt, cfm = std::nullopt;
};

#undef LINX_JOINT_HEAD
#undef LINX_JOINT_TAIL

/// The JointDef each typed definition stands for (createJoint(T::kType, toJointDef(def)) makes
/// the joint).
JointDef toJointDef(const FixedDef& def);
JointDef toJointDef(const SliderDef& def);
JointDef toJointDef(const HingeDef& def);
JointDef toJointDef(const BallDef& def);
JointDef toJointDef(const UniversalDef& def);
JointDef toJointDef(const CylindricalDef& def);
JointDef toJointDef(const Hinge2Def& def);
JointDef toJointDef(const DistanceDef& def);
JointDef toJointDef(const ConeTwistDef& def);
JointDef toJointDef(const PlanarDef& def);
JointDef toJointDef(const GearDef& def);
JointDef toJointDef(const GenericDef& def);
JointDef toJointDef(const SpringDef& def);
JointDef toJointDef(const RackAndPinionDef& def);
JointDef toJointDef(const SerialDef& def);
JointDef toJointDef(const MimicDef& def);

/// A typed joint definition: one of the structs above.
template <class T>
concept TypedJointDef = requires(const T& def) {
  { T::kType } -> std::convertible_to<std::string_view>;
  { toJointDef(def) } -> std::same_as<JointDef>;
};

}  // namespace linx
