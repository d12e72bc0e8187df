#include "state_arrays.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace py = pybind11;

namespace linx::python {

int fieldColumns(BodyField field) {
  return field == BodyField::Orientation ? 4 : 3;
}

const char* fieldName(BodyField field) {
  switch (field) {
    case BodyField::Position:
      return "positions";
    case BodyField::Orientation:
      return "orientations";
    case BodyField::LinearVelocity:
      return "linear_velocities";
    case BodyField::AngularVelocity:
      return "angular_velocities";
  }
  return "";
}

int readBody(const Body& b, BodyField field, double* out) {
  if (field == BodyField::Orientation) {
    const Quat& q = b.orientation();
    out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
    return 4;
  }
  const Vec3& v = field == BodyField::Position         ? b.position()
                  : field == BodyField::LinearVelocity ? b.linearVelocity()
                                                       : b.angularVelocity();
  std::copy_n(v.data(), 3, out);
  return 3;
}

void readBodies(const World& world, const std::vector<BodyId>& bodies, BodyField field,
                double* out) {
  for (const BodyId id : bodies) out += readBody(world.body(id), field, out);
}

void writeBodies(World& world, const std::vector<BodyId>& bodies, BodyField field,
                 const double* rows, const char* what) {
  const auto named = [&](std::size_t i, const Body& b) {
    return what != nullptr ? fmt::format("{} ({})", what, b.name())
                           : fmt::format("{}[{}] ({})", fieldName(field), i, b.name());
  };
  const int c = fieldColumns(field);
  // Checked in full before anything changes: a refused write leaves the world as it was.
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double* r = rows + i * static_cast<std::size_t>(c);
    const Body& b = world.body(bodies[i]);
    if (field == BodyField::Orientation && !unitQuaternion(r))
      throw py::value_error(fmt::format("{}: a zero quaternion is no rotation", named(i, b)));
    const bool velocity = field == BodyField::LinearVelocity || field == BodyField::AngularVelocity;
    if (velocity && b.isStatic() && Vec3(r[0], r[1], r[2]) != Vec3::Zero())
      throw py::value_error(fmt::format("{}: a static body does not move", named(i, b)));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double* r = rows + i * static_cast<std::size_t>(c);
    Body& b = world.body(bodies[i]);
    bool changed = false;
    switch (field) {
      case BodyField::Position: {
        const Vec3 p(r[0], r[1], r[2]);
        if (p != b.position()) b.setPose(Pose{p, b.orientation()}), changed = true;
        break;
      }
      case BodyField::Orientation: {
        const Quat q = *unitQuaternion(r);
        if (!q.coeffs().isApprox(b.orientation().coeffs(), 0.0))
          b.setPose(Pose{b.position(), q}), changed = true;
        break;
      }
      case BodyField::LinearVelocity: {
        const Vec3 v(r[0], r[1], r[2]);
        if (v != b.linearVelocity()) b.setLinearVelocity(v), changed = true;
        break;
      }
      case BodyField::AngularVelocity: {
        const Vec3 w(r[0], r[1], r[2]);
        if (w != b.angularVelocity()) b.setAngularVelocity(w), changed = true;
        break;
      }
    }
    if (changed) world.wake(bodies[i]);
  }
}

namespace {

using WorldClass = py::class_<PyWorld, std::shared_ptr<PyWorld>>;

void bindBodyField(WorldClass& c, BodyField field, const char* doc) {
  c.def_property(
      fieldName(field),
      [field](PyWorld& self) {
        const World& w = self.world();
        const auto n = static_cast<py::ssize_t>(self.bodies().size());
        auto a = newArray({n, fieldColumns(field)});
        readBodies(w, self.bodies(), field, a.mutable_data());
        return readOnly(std::move(a));
      },
      [field](PyWorld& self, py::handle value) {
        World& w = self.world();
        const auto n = static_cast<py::ssize_t>(self.bodies().size());
        const auto a = matrixArgument(value, n, fieldColumns(field), fieldName(field));
        writeBodies(w, self.bodies(), field, a.data());
      },
      doc);
}

/// One entry per joint of a quantity of up to kMaxCoordinates numbers, flattened.
template <typename PerJoint>
py::array_t<double> flatCoordinates(PyWorld& self, PerJoint&& perJoint) {
  const World& w = self.world();
  std::vector<double> values;
  for (const JointId id : self.joints()) {
    const JointCoordinates q = perJoint(w, id);
    values.insert(values.end(), q.data(), q.data() + q.size());
  }
  auto a = newArray({static_cast<py::ssize_t>(values.size())});
  std::copy(values.begin(), values.end(), a.mutable_data());
  return readOnly(std::move(a));
}

}  // namespace

void bindStateArrays(WorldClass& c) {
  bindBodyField(c, BodyField::Position,
                "Centres of mass (m, world frame), an array of bodies x 3 (a copy). Assign an "
                "array of that shape to move the bodies (they wake).");
  bindBodyField(c, BodyField::Orientation,
                "Orientations as unit quaternions (w, x, y, z), bodies x 4 (a copy). Assigned "
                "quaternions are normalized.");
  bindBodyField(c, BodyField::LinearVelocity,
                "Velocities of the centres of mass (m/s, world frame), bodies x 3 (a copy).");
  bindBodyField(c, BodyField::AngularVelocity,
                "Angular velocities (rad/s, world frame), bodies x 3 (a copy).");

  c.def(
      "body_state",
      [](PyWorld& self) {
        const World& w = self.world();
        const auto n = static_cast<py::ssize_t>(self.bodies().size());
        auto p = newArray({n, 3}), q = newArray({n, 4}), v = newArray({n, 3}), s = newArray({n, 3});
        double *po = p.mutable_data(), *qo = q.mutable_data(), *vo = v.mutable_data(),
               *so = s.mutable_data();
        for (const BodyId id : self.bodies()) {  // one pass over the bodies for all four
          const Body& b = w.body(id);
          po += readBody(b, BodyField::Position, po);
          qo += readBody(b, BodyField::Orientation, qo);
          vo += readBody(b, BodyField::LinearVelocity, vo);
          so += readBody(b, BodyField::AngularVelocity, so);
        }
        return py::make_tuple(readOnly(std::move(p)), readOnly(std::move(q)),
                              readOnly(std::move(v)), readOnly(std::move(s)));
      },
      "(positions, orientations, linear_velocities, angular_velocities) in one call: the four "
      "arrays of the properties, read in one pass over the bodies (the fastest way to read the "
      "whole state of many bodies).");
  c.def_property_readonly(
      "coordinates",
      [](PyWorld& self) {
        return flatCoordinates(self,
                               [](const World& w, JointId id) { return w.jointCoordinates(id); });
      },
      "Every joint's coordinates (hinge angle in rad, slider position in m, ...) one after "
      "another in joint order, named by coordinate_names (a copy).");
  c.def_property_readonly(
      "coordinate_rates",
      [](PyWorld& self) {
        return flatCoordinates(self, [](const World& w, JointId id) { return w.jointRates(id); });
      },
      "The rates of `coordinates` (m/s or rad/s) at the bodies' velocities (a copy).");
  c.def_property_readonly(
      "coordinate_names",
      [](PyWorld& self) {
        const World& w = self.world();
        py::list names;
        for (const JointId id : self.joints()) {
          const Joint& j = w.joint(id);
          const JointTypeInfo* info = findJointType(j.type());
          const auto n = w.jointCoordinates(id).size();
          for (Eigen::Index i = 0; i < n; ++i) {
            const bool named =
                info != nullptr && static_cast<std::size_t>(n) == info->coordinates.size();
            names.append(named ? fmt::format("{}.{}", j.name(), info->coordinates[i].name)
                               : fmt::format("{}.q{}", j.name(), i));
          }
        }
        return names;
      },
      "'JOINT.COORDINATE' for each entry of `coordinates` ('pivot.angle', 'rail.position').");
  c.def_property_readonly(
      "joint_errors",
      [](PyWorld& self) {
        const World& w = self.world();
        auto a = newArray({static_cast<py::ssize_t>(self.joints().size())});
        double* out = a.mutable_data();
        for (const JointId id : self.joints()) *out++ = w.jointError(id);
        return readOnly(std::move(a));
      },
      "Each joint's largest position error (m or rad), in joint order (a copy).");
  const auto reactions = [](bool torque) {
    return [torque](PyWorld& self) {
      const World& w = self.world();
      auto a = newArray({static_cast<py::ssize_t>(self.joints().size()), 3});
      double* out = a.mutable_data();
      for (const JointId id : self.joints()) {
        const JointReaction r = w.jointReaction(id);
        const Vec3& v = torque ? r.torque : r.force;
        out[0] = v.x(), out[1] = v.y(), out[2] = v.z();
        out += 3;
      }
      return readOnly(std::move(a));
    };
  };
  c.def_property_readonly("joint_forces", reactions(false),
                          "The force (N, world frame) each joint applied to its body1 over the "
                          "last step, joints x 3 (body2 received the opposite).");
  c.def_property_readonly("joint_torques", reactions(true),
                          "The torque (N m, world frame) each joint applied to its body1 over "
                          "the last step about its anchor, joints x 3.");

  bindContactArrays(c);
}

}  // namespace linx::python
