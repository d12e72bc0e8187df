// A joint given in its bodies' frames (JointDef::local) put in the world frame at creation: the
// form every joint type is made from.
#pragma once

#include <linx/joint.hpp>
#include <linx/types.hpp>

namespace linx::joints {

/// `def` with `anchor`, `axis` and `axes` taken from `frame1` (body 1's frame) and `anchor2` and
/// `axis2` from `frame2` (body 2's, the identity for the world) to the world, and `local` false.
/// A definition already in the world frame comes back as it is.
JointDef inWorldFrame(JointDef def, const Pose& frame1, const Pose& frame2);

}  // namespace linx::joints
