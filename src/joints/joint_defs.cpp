// The typed joint definitions as JointDefs: the common fields, then each type's own, its
// coordinates in the order its JointTypeInfo names them.
#include <linx/joint_defs.hpp>

namespace linx {

namespace {
// What every type has, bodies aside (a mimic joint's are the follower's).
template <class T>
JointDef named(const T& d) {
  JointDef j;
  j.name = d.name;
  j.break_force = d.break_force;
  j.break_torque = d.break_torque;
  j.erp = d.erp;
  j.cfm = d.cfm;
  return j;
}
template <class T>
JointDef common(const T& d) {
  JointDef j = named(d);
  j.body1 = d.body1;
  j.body2 = d.body2;
  j.local = d.local;
  j.collide = d.collide;
  return j;
}
}  // namespace

JointDef toJointDef(const FixedDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  return j;
}

JointDef toJointDef(const SliderDef& d) {
  JointDef j = common(d);
  j.axis = d.axis;
  j.coordinates[0] = d.position;
  return j;
}

JointDef toJointDef(const HingeDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis;
  j.coordinates[0] = d.angle;
  return j;
}

JointDef toJointDef(const BallDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.coordinates[0] = d.angle;
  return j;
}

JointDef toJointDef(const UniversalDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.coordinates[0] = d.angle1;
  j.coordinates[1] = d.angle2;
  return j;
}

JointDef toJointDef(const CylindricalDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis;
  j.coordinates[0] = d.position;
  j.coordinates[1] = d.angle;
  return j;
}

JointDef toJointDef(const Hinge2Def& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.coordinates[0] = d.wheel;
  j.coordinates[1] = d.steering;
  j.coordinates[2] = d.suspension;
  return j;
}

JointDef toJointDef(const DistanceDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor1;
  j.anchor2 = d.anchor2;
  j.length = d.length;
  j.rope = d.rope;
  return j;
}

JointDef toJointDef(const ConeTwistDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.cone = d.cone;
  j.coordinates[0] = d.twist;
  return j;
}

JointDef toJointDef(const PlanarDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.coordinates[0] = d.x;
  j.coordinates[1] = d.y;
  j.coordinates[2] = d.angle;
  return j;
}

JointDef toJointDef(const GearDef& d) {
  JointDef j = common(d);
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.ratio = d.ratio;
  return j;
}

JointDef toJointDef(const GenericDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor;
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.coordinates = {d.x, d.y, d.z, d.rx, d.ry, d.rz};
  return j;
}

JointDef toJointDef(const SpringDef& d) {
  JointDef j = common(d);
  j.anchor = d.anchor1;
  j.anchor2 = d.anchor2;
  j.coordinates[0] = d.length;
  return j;
}

JointDef toJointDef(const RackAndPinionDef& d) {
  JointDef j = common(d);
  j.axis = d.axis1;
  j.axis2 = d.axis2;
  j.ratio = d.ratio;
  return j;
}

JointDef toJointDef(const SerialDef& d) {
  JointDef j = common(d);
  for (std::size_t i = 0; i < d.axes.size(); ++i) {
    j.axes.push_back(SerialAxis{d.axes[i].linear, d.axes[i].axis, d.axes[i].anchor});
    // More than kMaxCoordinates axes: the world refuses the joint by its axes' count.
    if (i < j.coordinates.size()) j.coordinates[i] = d.axes[i].coordinate;
  }
  return j;
}

JointDef toJointDef(const MimicDef& d) {
  JointDef j = named(d);  // its bodies are the follower's (World::createJoint)
  j.leader = d.leader;
  j.follower = d.follower;
  j.ratio = d.ratio;
  j.offset = d.offset;
  return j;
}

}  // namespace linx
