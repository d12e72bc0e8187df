// linx.Body and linx.Joint: handles on one body or joint of a World, for reading it and for
// acting on it between steps (forces, drive targets, limits, springs).
#include "arguments.hpp"
#include "bindings.hpp"
#include "py_world.hpp"
#include "state_arrays.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>

#include <limits>
#include <optional>

namespace py = pybind11;

namespace linx::python {
namespace {

using WorldClass = py::class_<PyWorld, std::shared_ptr<PyWorld>>;

py::array_t<double> vec3(const Vec3& v) {
  auto a = newArray({3});
  std::copy(v.data(), v.data() + 3, a.mutable_data());
  return readOnly(std::move(a));
}

py::array_t<double> coordinatesArray(const JointCoordinates& q) {
  auto a = newArray({static_cast<py::ssize_t>(q.size())});
  std::copy(q.data(), q.data() + q.size(), a.mutable_data());
  return readOnly(std::move(a));
}

Body& bodyOf(BodyHandle& h) {
  return h.owner->world().body(h.id);
}
const Joint& jointOf(const JointHandle& h) {
  return h.owner->world().joint(h.id);
}

py::object bodyIndexOf(const PyWorld& owner, BodyId id) {
  const auto& ids = owner.bodies();
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ids[i] == id) return py::int_(i);
  return py::none();  // the world frame
}

/// Wakes the joint's bodies after a change of its drive, limits or spring.
void wakeJoint(JointHandle& h) {
  World& w = h.owner->world();
  const Joint& j = w.joint(h.id);
  for (const BodyId b : {j.body1(), j.body2()})
    if (!b.isWorld()) w.wake(b);
}

/// A coordinate index of joint h as the joints take it; one beyond an int is refused as they
/// refuse one out of their range (ValueError), naming the number given.
int coordinateIndex(JointHandle& h, const Index& coordinate) {
  if (coordinate.fitsInt()) return static_cast<int>(coordinate.value);
  const Joint& j = h.owner->world().joint(h.id);
  throw py::value_error(fmt::format("coordinate {}: joint '{}' has {} free coordinates",
                                    coordinate.text, j.def().name, j.freeCoordinates()));
}

/// Applies `edit` to joint h's Joint (set a motor, limits, ...) and wakes its bodies.
template <typename Edit>
void editJoint(JointHandle& h, Edit&& edit) {
  edit(h.owner->world().joint(h.id));
  wakeJoint(h);
}

/// A state property of one body, read and written as the World's arrays are (same checks).
void bindBodyField(py::class_<BodyHandle>& c, const char* name, BodyField field, const char* doc) {
  c.def_property(
      name,
      [field](const BodyHandle& h) {
        auto a = newArray({fieldColumns(field)});
        readBodies(h.owner->world(), {h.id}, field, a.mutable_data());
        return readOnly(std::move(a));
      },
      [field, name](const BodyHandle& h, py::handle value) {
        World& w = h.owner->world();
        const auto a = matrixArgument(value, fieldColumns(field), 0, name);
        writeBodies(w, {h.id}, field, a.data(), name);
      },
      doc);
}

void bindBody(py::module_& m) {
  py::class_<BodyHandle> c(m, "Body",
                           "A body of a World (World.body(), World.bodies). Reading and writing "
                           "go to the world; a handle of a closed world raises linx.ClosedError.");
  c.def_property_readonly(
       "world", [](const BodyHandle& h) { return h.owner; }, "Its world.")
      .def_property_readonly(
          "index", [](const BodyHandle& h) { return h.owner->world(), h.id.index; },
          "Its row in the world's arrays.")
      .def_property_readonly(
          "name", [](BodyHandle& h) { return bodyOf(h).name(); }, "Its name.")
      .def_property_readonly(
          "mass", [](BodyHandle& h) { return bodyOf(h).mass(); }, "(kg); 0 for a static body.")
      .def_property_readonly(
          "inertia",
          [](BodyHandle& h) {
            const Mat3& I = bodyOf(h).inertiaBody();
            auto a = newArray({3, 3});
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) a.mutable_at(r, c) = I(r, c);
            return readOnly(std::move(a));
          },
          "Inertia about the centre of mass in the body frame (kg m^2), 3 x 3.")
      .def_property_readonly(
          "is_static", [](BodyHandle& h) { return bodyOf(h).isStatic(); }, "Never moves.")
      .def_property_readonly(
          "is_kinematic", [](BodyHandle& h) { return bodyOf(h).isKinematic(); },
          "Moves at its own velocity, whatever pushes it.")
      .def(
          "apply_force",
          [](BodyHandle& h, py::handle force, py::handle point) {
            const Vec3 f = vectorArgument(force, "force");
            Body& b = bodyOf(h);
            if (point.is_none())
              b.applyForce(f);
            else
              b.applyForceAtPoint(f, vectorArgument(point, "point"));
            if (b.isDynamic()) h.owner->world().wake(h.id);
          },
          py::arg("force"), py::arg("point") = py::none(),
          "Adds a force (N, world frame) for the next step only, at the centre of mass or at a "
          "point (m, world frame). Nothing happens to a static or kinematic body.")
      .def(
          "apply_torque",
          [](BodyHandle& h, py::handle torque) {
            Body& b = bodyOf(h);
            b.applyTorque(vectorArgument(torque, "torque"));
            if (b.isDynamic()) h.owner->world().wake(h.id);
          },
          py::arg("torque"), "Adds a torque (N m, world frame) for the next step only.")
      .def_property_readonly(
          "kinetic_energy", [](BodyHandle& h) { return bodyOf(h).kineticEnergy(); }, "(J)")
      .def_property_readonly(
          "asleep", [](BodyHandle& h) { return h.owner->world().isAsleep(h.id); },
          "Its island is at rest and not integrated.")
      .def(
          "wake", [](BodyHandle& h) { h.owner->world().wake(h.id); },
          "Wakes it (and its island at the next step).")
      .def("__eq__",
           [](const BodyHandle& a, py::handle b) {
             return py::isinstance<BodyHandle>(b) && a.owner == b.cast<const BodyHandle&>().owner &&
                    a.id == b.cast<const BodyHandle&>().id;
           })
      .def("__hash__",
           [](const BodyHandle& h) {
             return py::hash(
                 py::make_tuple(reinterpret_cast<std::uintptr_t>(h.owner.get()), h.id.index));
           })
      .def("__repr__", [](BodyHandle& h) {
        if (h.owner->closed()) return fmt::format("<linx.Body {} of a closed world>", h.id.index);
        return fmt::format("<linx.Body {} '{}'>", h.id.index, bodyOf(h).name());
      });
  bindBodyField(c, "position", BodyField::Position, "Centre of mass (m, world frame).");
  bindBodyField(c, "orientation", BodyField::Orientation,
                "Unit quaternion (w, x, y, z) of the body frame; assigned ones are normalized.");
  bindBodyField(c, "linear_velocity", BodyField::LinearVelocity,
                "Velocity of the centre of mass (m/s, world frame).");
  bindBodyField(c, "angular_velocity", BodyField::AngularVelocity,
                "Angular velocity (rad/s, world frame).");
}

void bindJoint(py::module_& m) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  py::class_<JointHandle>(m, "Joint",
                          "A joint of a World (World.joint(), World.joints): its coordinates, "
                          "error and reaction, and its drives, limits and springs, changed "
                          "between steps. `coordinate` picks one of its free coordinates.")
      .def_property_readonly(
          "world", [](const JointHandle& h) { return h.owner; }, "Its world.")
      .def_property_readonly(
          "index", [](const JointHandle& h) { return h.owner->world(), h.id.index; },
          "Its place in joint order.")
      .def_property_readonly(
          "name", [](const JointHandle& h) { return jointOf(h).name(); }, "Its name.")
      .def_property_readonly(
          "type", [](const JointHandle& h) { return std::string(jointOf(h).type()); },
          "'hinge', 'slider', 'ball', ...")
      .def_property_readonly(
          "body1", [](const JointHandle& h) { return bodyIndexOf(*h.owner, jointOf(h).body1()); },
          "Index of its first body (None: the world).")
      .def_property_readonly(
          "body2", [](const JointHandle& h) { return bodyIndexOf(*h.owner, jointOf(h).body2()); },
          "Index of its second body (None: the world).")
      .def_property_readonly(
          "coordinates",
          [](const JointHandle& h) {
            return coordinatesArray(h.owner->world().jointCoordinates(h.id));
          },
          "Its coordinates (rad or m), zero where it was built (with its reference).")
      .def_property_readonly(
          "rates",
          [](const JointHandle& h) { return coordinatesArray(h.owner->world().jointRates(h.id)); },
          "The coordinates' rates (rad/s or m/s).")
      .def_property_readonly(
          "free_coordinates", [](const JointHandle& h) { return jointOf(h).freeCoordinates(); },
          "How many coordinates take limits, drives and springs (the first ones).")
      .def_property_readonly(
          "error", [](const JointHandle& h) { return h.owner->world().jointError(h.id); },
          "Its largest position error (m or rad).")
      .def_property_readonly(
          "force",
          [](const JointHandle& h) { return vec3(h.owner->world().jointReaction(h.id).force); },
          "The force (N, world frame) it applied to body1 over the last step.")
      .def_property_readonly(
          "torque",
          [](const JointHandle& h) { return vec3(h.owner->world().jointReaction(h.id).torque); },
          "The torque (N m, world frame) it applied to body1 about its anchor over the last step.")
      .def_property(
          "enabled", [](const JointHandle& h) { return jointOf(h).enabled(); },
          [](JointHandle& h, bool on) { editJoint(h, [on](Joint& j) { j.setEnabled(on); }); },
          "A disabled joint (broken, or switched off) has no rows.")
      .def(
          "set_motor",
          [](JointHandle& h, double target_velocity, double max_force,
             std::optional<double> target_position, double stiffness, double damping,
             const Index& coordinate) {
            JointMotor motor;
            motor.target_velocity = target_velocity;
            motor.max_force = max_force;
            if (target_position) motor.target_position = Signal(*target_position);
            motor.stiffness = stiffness;
            motor.damping = damping;
            editJoint(h, [&](Joint& j) { j.setMotor(motor, coordinateIndex(h, coordinate)); });
          },
          py::kw_only(), py::arg("target_velocity") = 0.0, py::arg("max_force") = kInf,
          py::arg("target_position") = py::none(), py::arg("stiffness") = 0.0,
          py::arg("damping") = 0.0, py::arg("coordinate") = 0,
          "Sets the coordinate's drive (docs/joints.md): a velocity motor holding "
          "target_velocity (m/s or rad/s) with at most max_force (N or N m), or with "
          "target_position a PD servo F = stiffness (target_position - x) + damping "
          "(target_velocity - x'). Raises ValueError for values the joint refuses.")
      .def(
          "clear_motor",
          [](JointHandle& h, const Index& coordinate) {
            editJoint(h,
                      [&](Joint& j) { j.setMotor(std::nullopt, coordinateIndex(h, coordinate)); });
          },
          py::kw_only(), py::arg("coordinate") = 0, "Removes the coordinate's drive.")
      .def(
          "set_limits",
          [](JointHandle& h, double lower, double upper, const Index& coordinate) {
            editJoint(h, [&](Joint& j) {
              j.setLimits(JointLimits{lower, upper}, coordinateIndex(h, coordinate));
            });
          },
          py::kw_only(), py::arg("lower") = -kInf, py::arg("upper") = kInf,
          py::arg("coordinate") = 0, "Sets the coordinate's limits (m or rad).")
      .def(
          "clear_limits",
          [](JointHandle& h, const Index& coordinate) {
            editJoint(h,
                      [&](Joint& j) { j.setLimits(std::nullopt, coordinateIndex(h, coordinate)); });
          },
          py::kw_only(), py::arg("coordinate") = 0, "Removes the coordinate's limits.")
      .def(
          "set_spring",
          [](JointHandle& h, double stiffness, double damping, double rest,
             const Index& coordinate) {
            editJoint(h, [&](Joint& j) {
              j.setSpring(JointSpring{stiffness, damping, rest}, coordinateIndex(h, coordinate));
            });
          },
          py::kw_only(), py::arg("stiffness"), py::arg("damping") = 0.0, py::arg("rest") = 0.0,
          py::arg("coordinate") = 0,
          "Sets a spring-damper on the coordinate: F = -stiffness (x - rest) - damping x'.")
      .def(
          "clear_spring",
          [](JointHandle& h, const Index& coordinate) {
            editJoint(h,
                      [&](Joint& j) { j.setSpring(std::nullopt, coordinateIndex(h, coordinate)); });
          },
          py::kw_only(), py::arg("coordinate") = 0, "Removes the coordinate's spring.")
      .def(
          "set_force",
          [](JointHandle& h, std::optional<double> force, const Index& coordinate) {
            std::optional<Signal> signal;
            if (force) signal = Signal(*force);
            editJoint(h, [&](Joint& j) { j.setForce(signal, coordinateIndex(h, coordinate)); });
          },
          py::arg("force"), py::kw_only(), py::arg("coordinate") = 0,
          "Applies a force (N) or torque (N m) along the coordinate at every step from now on "
          "(an actuator's effort); None removes it.")
      .def(
          "set_coordinate",
          [](JointHandle& h, double value, const Index& coordinate) {
            h.owner->world().setJointCoordinate(h.id, coordinateIndex(h, coordinate), value);
          },
          py::arg("value"), py::kw_only(), py::arg("coordinate") = 0,
          "Moves body1's side of the mechanism so that the coordinate reads `value` (a model "
          "built straight, started bent). Raises ValueError in a closed loop.")
      .def("__eq__",
           [](const JointHandle& a, py::handle b) {
             return py::isinstance<JointHandle>(b) &&
                    a.owner == b.cast<const JointHandle&>().owner &&
                    a.id == b.cast<const JointHandle&>().id;
           })
      .def("__hash__",
           [](const JointHandle& h) {
             return py::hash(
                 py::make_tuple(reinterpret_cast<std::uintptr_t>(h.owner.get()), h.id.index, 1));
           })
      .def("__repr__", [](const JointHandle& h) {
        if (h.owner->closed()) return fmt::format("<linx.Joint {} of a closed world>", h.id.index);
        const Joint& j = jointOf(h);
        return fmt::format("<linx.Joint {} '{}' ({})>", h.id.index, j.name(), j.type());
      });
}

}  // namespace

void bindHandles(py::module_& m, WorldClass& world) {
  bindBody(m);
  bindJoint(m);
  world.def(
      "body",
      [](std::shared_ptr<PyWorld> self, py::handle key) {
        return BodyHandle{self, python::bodyOf(self, key)};
      },
      py::arg("key"), "The body named by an index (negative from the end) or a name.");
  world.def(
      "joint",
      [](std::shared_ptr<PyWorld> self, py::handle key) {
        return JointHandle{self, python::jointOf(self, key)};
      },
      py::arg("key"), "The joint named by an index (negative from the end) or a name.");
  world.def_property_readonly(
      "bodies",
      [](std::shared_ptr<PyWorld> self) {
        self->world();
        std::vector<BodyHandle> all;
        for (const BodyId id : self->bodies()) all.push_back(BodyHandle{self, id});
        return all;
      },
      "Every body, in order.");
  world.def_property_readonly(
      "joints",
      [](std::shared_ptr<PyWorld> self) {
        self->world();
        std::vector<JointHandle> all;
        for (const JointId id : self->joints()) all.push_back(JointHandle{self, id});
        return all;
      },
      "Every joint, in order.");
  world.def(
      "apply_force",
      [](std::shared_ptr<PyWorld> self, py::handle body, py::handle force, py::handle point) {
        BodyHandle h{self, python::bodyOf(self, body)};
        py::cast(h).attr("apply_force")(force, point);
      },
      py::arg("body"), py::arg("force"), py::arg("point") = py::none(),
      "Body(body).apply_force(force, point): `body` an index, a name or a Body of this world.");
  world.def(
      "apply_torque",
      [](std::shared_ptr<PyWorld> self, py::handle body, py::handle torque) {
        BodyHandle h{self, python::bodyOf(self, body)};
        py::cast(h).attr("apply_torque")(torque);
      },
      py::arg("body"), py::arg("torque"),
      "Body(body).apply_torque(torque): `body` an index, a name or a Body of this world.");
}

}  // namespace linx::python
