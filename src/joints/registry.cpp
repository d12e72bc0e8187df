// The joint types known by name. Adding a type: its own file, and one line in kTypes.
#include "joints/ball_joint.hpp"
#include "joints/cone_twist_joint.hpp"
#include "joints/cylindrical_joint.hpp"
#include "joints/distance_joint.hpp"
#include "joints/fixed_joint.hpp"
#include "joints/gear_joint.hpp"
#include "joints/generic_joint.hpp"
#include "joints/hinge2_joint.hpp"
#include "joints/hinge_joint.hpp"
#include "joints/mimic_joint.hpp"
#include "joints/planar_joint.hpp"
#include "joints/rack_pinion_joint.hpp"
#include "joints/serial_joint.hpp"
#include "joints/slider_joint.hpp"
#include "joints/spring_joint.hpp"
#include "joints/universal_joint.hpp"
#include "joints/validation.hpp"
#include "schema/check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace linx {

namespace {

using Coupled = std::array<const Joint*, 2>;
using Maker = std::unique_ptr<Joint> (*)(const JointDef&, const BodyState&, const BodyState&,
                                         Coupled);

template <class T>
std::unique_ptr<Joint> make(const JointDef& def, const BodyState& b1, const BodyState& b2,
                            Coupled) {
  return std::make_unique<T>(def, b1, b2);
}
// A type that ties joints gets them (World::createJoint checks they are there).
template <class T>
std::unique_ptr<Joint> makeCoupling(const JointDef& def, const BodyState&, const BodyState&,
                                    Coupled joints) {
  return std::make_unique<T>(def, *joints[0], *joints[1]);
}

constexpr CoordinateInfo kPosition[] = {{"position", true}};
constexpr CoordinateInfo kAngle[] = {{"angle", false}};
constexpr CoordinateInfo kTwoAngles[] = {{"angle1", false}, {"angle2", false}};
constexpr CoordinateInfo kPositionAngle[] = {{"position", true}, {"angle", false}};
constexpr CoordinateInfo kWheel[] = {{"wheel", false}, {"steering", false}, {"suspension", true}};
constexpr CoordinateInfo kSixAxes[] = {{"x", true},   {"y", true},   {"z", true},
                                       {"rx", false}, {"ry", false}, {"rz", false}};
constexpr CoordinateInfo kTwistSwing[] = {{"twist", false}, {"swing", false, false}};
constexpr CoordinateInfo kPlane[] = {{"x", true}, {"y", true}, {"angle", false}};
constexpr CoordinateInfo kGearAngles[] = {{"angle1", false, false}, {"angle2", false, false}};
constexpr CoordinateInfo kLength[] = {{"length", true, false}};  // reported, not driven
constexpr CoordinateInfo kFreeLength[] = {{"length", true}};
constexpr CoordinateInfo kRackPinion[] = {{"angle", false, false}, {"position", true, false}};
// Limited only (an upper bound on the rotation angle), not driven.
constexpr CoordinateInfo kBallAngle[] = {{"angle", false, true, true}};
// A serial joint's are its axes' (JointDef::axes), angles or positions as each axis is.
constexpr CoordinateInfo kSerial[] = {{"axes[0]"}, {"axes[1]"}, {"axes[2]"},
                                      {"axes[3]"}, {"axes[4]"}, {"axes[5]"}};

// Each type's own fields, in the order files and docs give them; required ones marked.
using F = JointField;
constexpr TypeField kPoint[] = {{F::Anchor}};
constexpr TypeField kSliderFields[] = {{F::Anchor}, {F::Axis, true}};
constexpr TypeField kPointAxis[] = {{F::Anchor, true}, {F::Axis, true}};
constexpr TypeField kPivot[] = {{F::Anchor, true}};
constexpr TypeField kPointFrame[] = {{F::Anchor, true}, {F::Axis1, true}, {F::Axis2, true}};
constexpr TypeField kDistanceFields[] = {{F::Anchor1}, {F::Anchor2}, {F::Length}, {F::Rope}};
constexpr TypeField kConeTwistFields[] = {
    {F::Anchor, true}, {F::Axis1, true}, {F::Axis2, true}, {F::Cone}};
constexpr TypeField kGeared[] = {{F::Anchor}, {F::Axis1, true}, {F::Axis2, true}, {F::Ratio, true}};
constexpr TypeField kTwoPoints[] = {{F::Anchor1}, {F::Anchor2}};
constexpr TypeField kSerialFields[] = {{F::Anchor}, {F::Axes, true}};
constexpr TypeField kMimicFields[] = {
    {F::Leader, true}, {F::Follower, true}, {F::Ratio}, {F::Offset}};

// One line per type: its fields and coordinates, and how it is made.
struct Registered {
  JointTypeInfo info;
  Maker make;
};
constexpr auto kTypes = std::to_array<Registered>({
    {{"fixed", kPoint}, &make<joints::FixedJoint>},
    {{"slider", kSliderFields, kPosition}, &make<joints::SliderJoint>},
    {{"hinge", kPointAxis, kAngle}, &make<joints::HingeJoint>},
    {{"ball", kPivot, kBallAngle}, &make<joints::BallJoint>},
    {{"universal", kPointFrame, kTwoAngles}, &make<joints::UniversalJoint>},
    {{"cylindrical", kPointAxis, kPositionAngle}, &make<joints::CylindricalJoint>},
    {{"hinge2", kPointFrame, kWheel}, &make<joints::Hinge2Joint>},
    {{"distance", kDistanceFields, kLength}, &make<joints::DistanceJoint>},
    {{"cone_twist", kConeTwistFields, kTwistSwing}, &make<joints::ConeTwistJoint>},
    {{"planar", kPointFrame, kPlane}, &make<joints::PlanarJoint>},
    {{"gear", kGeared, kGearAngles}, &make<joints::GearJoint>},
    {{"generic", kPointFrame, kSixAxes}, &make<joints::GenericJoint>},
    {{"spring", kTwoPoints, kFreeLength}, &make<joints::SpringJoint>},
    {{"rack_and_pinion", kGeared, kRackPinion}, &make<joints::RackPinionJoint>},
    {{"serial", kSerialFields, kSerial}, &make<joints::SerialJoint>},
    {{"mimic", kMimicFields}, &makeCoupling<joints::MimicJoint>},
});
constexpr std::array<JointTypeInfo, kTypes.size()> kInfo = [] {
  std::array<JointTypeInfo, kTypes.size()> info{};
  for (std::size_t i = 0; i < kTypes.size(); ++i) info[i] = kTypes[i].info;
  return info;
}();

}  // namespace

namespace joints {
void validate(const JointTypeInfo& t, const JointDef& def) {
  if (def.anchor && !def.anchor->allFinite())
    throw std::invalid_argument("anchor: not a finite vector");
  if (t.usesAxis() && !(def.axis.allFinite() && def.axis.norm() > 1e-12))
    throw std::invalid_argument("axis: must be a finite non-zero vector");
  if (t.usesAxis2() && !(def.axis2.allFinite() && def.axis2.norm() > 1e-12))
    throw std::invalid_argument("axis2: must be a finite non-zero vector");
  // Two axes are a frame's (a cross's arms, a plane's x and y), except a gear's two axles.
  if (t.usesAxis2() && !t.uses(JointField::Ratio)) {
    const double cosine = def.axis.normalized().dot(def.axis2.normalized());
    if (std::abs(cosine) > 1e-6)
      throw std::invalid_argument(
          fmt::format("axis2: must be perpendicular to axis1 (they are {:.6g} deg apart)",
                      std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI));
  }
  if (t.usesAnchor2() && def.anchor2 && !def.anchor2->allFinite())
    throw std::invalid_argument("anchor2: not a finite vector");
  if (t.uses(JointField::Length)) {
    if (def.length && !(std::isfinite(*def.length) && *def.length > 0.0))
      throw std::invalid_argument("length: must be finite and > 0");
  } else if (def.length || def.rope) {
    throw std::invalid_argument(
        fmt::format("{}: not used by a {} joint", def.length ? "length" : "rope", t.name));
  }
  if (t.usesAxes()) {
    validateAxes(def.axes);
  } else if (!def.axes.empty()) {
    throw std::invalid_argument(fmt::format("axes: not used by a {} joint", t.name));
  }
  if (t.uses(JointField::Ratio) && !(std::isfinite(def.ratio) && def.ratio != 0.0))
    throw std::invalid_argument("ratio: must be finite and non-zero");
  if (t.couplesJoints() && !std::isfinite(def.offset))
    throw std::invalid_argument("offset: must be finite");
  if (def.cone) {
    if (!t.uses(JointField::Cone))
      throw std::invalid_argument(fmt::format("cone: not used by a {} joint", t.name));
    for (const double s : {def.cone->swing1, def.cone->swing2})
      if (!(s > 0.0 && s < M_PI))
        throw std::invalid_argument("cone: swing1 and swing2 must be in (0, pi) rad");
  }
  for (const auto& [field, value] :
       {std::pair{"break_force", def.break_force}, std::pair{"break_torque", def.break_torque}})
    if (value && !(std::isfinite(*value) && *value > 0.0))
      throw std::invalid_argument(fmt::format("{}: must be finite and > 0", field));
  if (def.erp && !(*def.erp >= 0.0 && *def.erp <= 1.0))
    throw std::invalid_argument("erp: must be in [0, 1]");
  if (def.cfm && !(*def.cfm >= 0.0 && std::isfinite(*def.cfm)))
    throw std::invalid_argument("cfm: must be finite and >= 0");
  const int free = t.freeCoordinates(def);
  for (int i = 0; i < kMaxCoordinates; ++i) {
    const CoordinateDef& c = def.coordinates[static_cast<std::size_t>(i)];
    if (i >= free) {
      if (c.empty() && c.reference == 0.0 && !c.initial)
        continue;
      else if (free == 0)
        throw std::invalid_argument(
            fmt::format("a {} joint takes no limits, motor, spring or friction", t.name));
      else
        throw std::invalid_argument(
            fmt::format("coordinates[{}]: a {} joint has {} free "
                        "coordinates",
                        i, t.name, free));
    }
    // Messages name the coordinate as scene files do: "angle1.limits: ...", "axes[1].limits: ...",
    // or "limits: ..." for a joint with one.
    const std::string prefix =
        free == 1 && !t.usesAxes()
            ? ""
            : fmt::format("{}.", t.coordinates[static_cast<std::size_t>(i)].name);
    validateCoordinate(c, prefix);
    if (t.coordinates[static_cast<std::size_t>(i)].limits_only) limitsOnly(t, c, prefix);
  }
}

void limitsOnly(const JointTypeInfo& t, const CoordinateDef& c, const std::string& prefix) {
  CoordinateDef rest = c;
  rest.limits.reset();
  if (!rest.empty() || rest.reference != 0.0 || rest.initial)
    throw std::invalid_argument(
        fmt::format("{}limits are all a {} joint's angle takes (no motor, spring, friction, lock, "
                    "prescribed motion, armature, force, reference or initial value)",
                    prefix, t.name));
  if (c.limits && c.limits->lower > 0.0)
    throw std::invalid_argument(fmt::format(
        "{}limits.lower: a {} joint's angle is >= 0: give only its upper bound", prefix, t.name));
  if (c.limits && !(c.limits->upper >= 0.0 && c.limits->upper < M_PI))
    throw std::invalid_argument(fmt::format(
        "{}limits.upper: a {} joint's angle bound must be in [0, pi) rad", prefix, t.name));
}

void validateAxes(const std::vector<SerialAxis>& axes) {
  if (axes.empty() || axes.size() > static_cast<std::size_t>(kMaxCoordinates))
    throw std::invalid_argument(
        fmt::format("axes: a serial joint has 1 to {} axes, not {}", kMaxCoordinates, axes.size()));
  for (std::size_t i = 0; i < axes.size(); ++i) {
    if (!(axes[i].axis.allFinite() && axes[i].axis.norm() > 1e-12))
      throw std::invalid_argument(
          fmt::format("axes[{}].axis: must be a finite non-zero vector", i));
    if (!axes[i].anchor.allFinite())
      throw std::invalid_argument(fmt::format("axes[{}].anchor: not a finite vector", i));
  }
}

// Each field within its bounds and the coordinate's rules, as the scene format describes them
// (src/schema/describe.hpp).
void validateCoordinate(const CoordinateDef& c, const std::string& prefix) {
  schema::check(c, prefix);
}

void validateSignal(const Signal& s, std::string_view field) {
  schema::checkSignal(s, std::string(field));
}

void validateMotor(const JointMotor& m) {
  schema::check(m, "motor.");
}

void validateSpring(const JointSpring& s) {
  schema::check(s, "spring.");
}

}  // namespace joints

std::string_view jointFieldName(JointField field) {
  static constexpr std::string_view kNames[] = {"anchor", "anchor1", "anchor2",  "axis",  "axis1",
                                                "axis2",  "length",  "rope",     "cone",  "ratio",
                                                "axes",   "leader",  "follower", "offset"};
  return kNames[static_cast<std::size_t>(field)];
}

bool JointTypeInfo::uses(JointField field) const {
  return std::any_of(fields.begin(), fields.end(),
                     [&](const TypeField& f) { return f.field == field; });
}

bool JointTypeInfo::needs(JointField field) const {
  return std::any_of(fields.begin(), fields.end(),
                     [&](const TypeField& f) { return f.field == field && f.required; });
}

int JointTypeInfo::freeCoordinates() const {
  int n = 0;
  while (n < static_cast<int>(coordinates.size()) && coordinates[static_cast<std::size_t>(n)].free)
    ++n;
  return n;
}

int JointTypeInfo::freeCoordinates(const JointDef& def) const {
  return usesAxes() ? static_cast<int>(def.axes.size()) : freeCoordinates();
}

std::span<const JointTypeInfo> jointTypes() {
  return kInfo;
}

const JointTypeInfo* findJointType(std::string_view type) {
  for (const JointTypeInfo& t : kInfo)
    if (t.name == type) return &t;
  return nullptr;
}

bool isJointType(std::string_view type) {
  return findJointType(type) != nullptr;
}

std::unique_ptr<Joint> makeJoint(std::string_view type, const JointDef& def, const BodyState& b1,
                                 const BodyState& b2, std::array<const Joint*, 2> coupled) {
  const JointTypeInfo* t = findJointType(type);
  if (!t) throw std::invalid_argument(fmt::format("unknown joint type '{}'", type));
  if (t->couplesJoints() && !(coupled[0] && coupled[1]))
    throw std::invalid_argument(
        fmt::format("a {} joint ties two joints: its leader and follower are needed", t->name));
  if (t->needs(JointField::Anchor) && !def.anchor)
    throw std::invalid_argument(
        fmt::format("anchor: a {} joint needs one (the point it turns about)", t->name));
  JointDef resolved = def;
  if (!resolved.anchor) resolved.anchor = b1.pose.position;
  joints::validate(*t, resolved);
  std::unique_ptr<Joint> joint =
      kTypes[static_cast<std::size_t>(t - kInfo.data())].make(resolved, b1, b2, coupled);
  joint->anchor1_ = b1.pose.toLocal(*resolved.anchor);
  return joint;
}

}  // namespace linx
