// The joint types known by name. Adding a type: its own file, and one line in kTypes below.
#include "joints/ball_joint.hpp"
#include "joints/fixed_joint.hpp"
#include "joints/hinge_joint.hpp"
#include "joints/slider_joint.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>

namespace linx {

namespace {

struct JointType {
  std::string_view name;
  bool has_axis;        // uses JointDef::axis
  bool has_coordinate;  // accepts limits and a motor
  std::unique_ptr<Joint> (*make)(const JointDef&, const BodyState&, const BodyState&);
};

template <class T>
std::unique_ptr<Joint> make(const JointDef& def, const BodyState& b1, const BodyState& b2) {
  return std::make_unique<T>(def, b1, b2);
}

constexpr std::array kTypes{
    JointType{"fixed", false, false, &make<joints::FixedJoint>},
    JointType{"slider", true, true, &make<joints::SliderJoint>},
    JointType{"hinge", true, true, &make<joints::HingeJoint>},
    JointType{"ball", false, false, &make<joints::BallJoint>},
};

const JointType* find(std::string_view name) {
  for (const JointType& t : kTypes)
    if (t.name == name) return &t;
  return nullptr;
}

void validate(const JointType& t, const JointDef& def) {
  if (!def.anchor.allFinite()) throw std::invalid_argument("anchor: not a finite vector");
  if (t.has_axis && !(def.axis.allFinite() && def.axis.norm() > 1e-12))
    throw std::invalid_argument("axis: must be a finite non-zero vector");
  if (def.erp && !(*def.erp >= 0.0 && *def.erp <= 1.0))
    throw std::invalid_argument("erp: must be in [0, 1]");
  if (def.cfm && !(*def.cfm >= 0.0 && std::isfinite(*def.cfm)))
    throw std::invalid_argument("cfm: must be finite and >= 0");
  if (!t.has_coordinate && (def.limits || def.motor))
    throw std::invalid_argument(fmt::format("a {} joint takes no limits or motor", t.name));
  if (def.limits && !(def.limits->lower <= def.limits->upper))
    throw std::invalid_argument("limits: lower must not exceed upper");
  if (def.motor && !(std::isfinite(def.motor->target_velocity) &&
                     std::isfinite(def.motor->max_force) && def.motor->max_force >= 0.0))
    throw std::invalid_argument("motor: needs a finite target_velocity and max_force >= 0");
}

}  // namespace

bool isJointType(std::string_view type) {
  return find(type) != nullptr;
}

std::unique_ptr<Joint> makeJoint(std::string_view type, const JointDef& def, const BodyState& b1,
                                 const BodyState& b2) {
  const JointType* t = find(type);
  if (!t) throw std::invalid_argument(fmt::format("unknown joint type '{}'", type));
  validate(*t, def);
  return t->make(def, b1, b2);
}

}  // namespace linx
