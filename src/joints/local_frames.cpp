#include "joints/local_frames.hpp"

namespace linx::joints {

JointDef inWorldFrame(JointDef def, const Pose& frame1, const Pose& frame2) {
  if (!def.local) return def;
  def.local = false;
  if (def.anchor) def.anchor = frame1.toWorld(*def.anchor);
  if (def.anchor2) def.anchor2 = frame2.toWorld(*def.anchor2);
  def.axis = frame1.orientation * def.axis;
  def.axis2 = frame2.orientation * def.axis2;
  for (SerialAxis& a : def.axes) {
    a.axis = frame1.orientation * a.axis;
    a.anchor = frame1.toWorld(a.anchor);
  }
  return def;
}

}  // namespace linx::joints
