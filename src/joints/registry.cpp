// The joint types known by name. Adding a type: its own file, and one line in kInfo and kMake.
#include "joints/ball_joint.hpp"
#include "joints/fixed_joint.hpp"
#include "joints/hinge_joint.hpp"
#include "joints/slider_joint.hpp"
#include "joints/universal_joint.hpp"
#include "joints/validation.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>

namespace linx {

namespace {

using Maker = std::unique_ptr<Joint> (*)(const JointDef&, const BodyState&, const BodyState&);

template <class T>
std::unique_ptr<Joint> make(const JointDef& def, const BodyState& b1, const BodyState& b2) {
  return std::make_unique<T>(def, b1, b2);
}

//                      name         anchor axis   axis2  coordinate
constexpr std::array<JointTypeInfo, 5> kInfo{{{"fixed", false, false, false, false},
                                              {"slider", false, true, false, true},
                                              {"hinge", true, true, false, true},
                                              {"ball", true, false, false, false},
                                              {"universal", true, true, true, false}}};
constexpr std::array<Maker, kInfo.size()> kMake{
    &make<joints::FixedJoint>, &make<joints::SliderJoint>, &make<joints::HingeJoint>,
    &make<joints::BallJoint>, &make<joints::UniversalJoint>};

}  // namespace

namespace joints {
void validate(const JointTypeInfo& t, const JointDef& def) {
  if (def.anchor && !def.anchor->allFinite())
    throw std::invalid_argument("anchor: not a finite vector");
  if (t.uses_axis && !(def.axis.allFinite() && def.axis.norm() > 1e-12))
    throw std::invalid_argument("axis: must be a finite non-zero vector");
  if (t.uses_axis2 && !(def.axis2.allFinite() && def.axis2.norm() > 1e-12))
    throw std::invalid_argument("axis2: must be a finite non-zero vector");
  if (def.erp && !(*def.erp >= 0.0 && *def.erp <= 1.0))
    throw std::invalid_argument("erp: must be in [0, 1]");
  if (def.cfm && !(*def.cfm >= 0.0 && std::isfinite(*def.cfm)))
    throw std::invalid_argument("cfm: must be finite and >= 0");
  if (!t.has_coordinate && (def.limits || def.motor || def.spring))
    throw std::invalid_argument(fmt::format("a {} joint takes no limits, motor or spring", t.name));
  if (def.limits && !(def.limits->lower <= def.limits->upper))
    throw std::invalid_argument("limits: lower must not exceed upper");
  if (def.motor) validateMotor(*def.motor);
  if (def.spring) validateSpring(*def.spring);
}

void validateSignal(const Signal& s, std::string_view field) {
  const auto bad = [&](const std::string& problem) {
    return std::invalid_argument(fmt::format("{}: {}", field, problem));
  };
  if (s.times.empty()) {
    if (s.values.size() != 1 || !std::isfinite(s.values[0])) throw bad("must be finite");
    return;
  }
  if (s.values.size() != s.times.size())
    throw bad(fmt::format("{} times but {} values", s.times.size(), s.values.size()));
  for (std::size_t i = 0; i < s.times.size(); ++i) {
    if (!std::isfinite(s.times[i])) throw bad(fmt::format("times[{}]: must be finite", i));
    if (!std::isfinite(s.values[i])) throw bad(fmt::format("values[{}]: must be finite", i));
    if (i > 0 && !(s.times[i] > s.times[i - 1]))
      throw bad(fmt::format("times[{}]: must be after times[{}] ({} <= {})", i, i - 1, s.times[i],
                            s.times[i - 1]));
  }
}

void validateMotor(const JointMotor& m) {
  const auto gain = [](double v) { return std::isfinite(v) && v >= 0.0; };
  validateSignal(m.target_velocity, "motor.target_velocity");
  if (!(m.max_force >= 0.0)) throw std::invalid_argument("motor.max_force: must be >= 0");
  if (!gain(m.stiffness)) throw std::invalid_argument("motor.stiffness: must be finite and >= 0");
  if (!gain(m.damping)) throw std::invalid_argument("motor.damping: must be finite and >= 0");
  if (m.target_position) {
    validateSignal(*m.target_position, "motor.target_position");
    if (!(m.stiffness > 0.0))
      throw std::invalid_argument("motor.stiffness: a servo (target_position) needs stiffness > 0");
  } else if (m.stiffness > 0.0) {
    throw std::invalid_argument("motor.stiffness: needs a target_position to pull towards");
  }
}

void validateSpring(const JointSpring& s) {
  const auto gain = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!gain(s.stiffness)) throw std::invalid_argument("spring.stiffness: must be finite and >= 0");
  if (!gain(s.damping)) throw std::invalid_argument("spring.damping: must be finite and >= 0");
  if (!std::isfinite(s.rest)) throw std::invalid_argument("spring.rest: must be finite");
}

}  // namespace joints

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
                                 const BodyState& b2) {
  const JointTypeInfo* t = findJointType(type);
  if (!t) throw std::invalid_argument(fmt::format("unknown joint type '{}'", type));
  if (t->needs_anchor && !def.anchor)
    throw std::invalid_argument(
        fmt::format("anchor: a {} joint needs one (the point it turns about)", t->name));
  JointDef resolved = def;
  if (!resolved.anchor) resolved.anchor = b1.pose.position;
  joints::validate(*t, resolved);
  std::unique_ptr<Joint> joint =
      kMake[static_cast<std::size_t>(t - kInfo.data())](resolved, b1, b2);
  joint->anchor1_ = b1.pose.toLocal(*resolved.anchor);
  return joint;
}

}  // namespace linx
