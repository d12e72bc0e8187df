// World.contacts: the last step's contact points as arrays, one entry per point.
#include "state_arrays.hpp"

namespace py = pybind11;

namespace linx::python {
namespace {

struct ContactArrays {
  py::array_t<long long> body1, body2;
  py::array_t<double> point, normal, depth, normal_impulse, friction_impulse;
};

}  // namespace

void bindContactArrays(py::class_<PyWorld, std::shared_ptr<PyWorld>>& c) {
  py::class_<ContactArrays>(c, "Contacts",
                            "The contact points of the last step, one entry per point.")
      .def_readonly("body1", &ContactArrays::body1, "Index of the first body of each contact.")
      .def_readonly("body2", &ContactArrays::body2, "Index of the second body (never the world).")
      .def_readonly("point", &ContactArrays::point, "Points (m, world), midway between surfaces.")
      .def_readonly("normal", &ContactArrays::normal, "Unit normals from body1 towards body2.")
      .def_readonly("depth", &ContactArrays::depth,
                    "Penetration at the step's start (m); negative: a gap.")
      .def_readonly("normal_impulse", &ContactArrays::normal_impulse,
                    "Impulse on body2 along the normal (N s); body1 got the opposite.")
      .def_readonly("friction_impulse", &ContactArrays::friction_impulse,
                    "Tangential impulse on body2 (N s, world frame).")
      .def("__len__", [](const ContactArrays& a) { return a.depth.size(); });
  c.def_property_readonly(
      "contacts",
      [](PyWorld& self) {
        const auto contacts = self.world().contacts();
        const auto n = static_cast<py::ssize_t>(contacts.size());
        ContactArrays a{py::array_t<long long>(n),
                        py::array_t<long long>(n),
                        newArray({n, 3}),
                        newArray({n, 3}),
                        newArray({n}),
                        newArray({n}),
                        newArray({n, 3})};
        for (py::ssize_t i = 0; i < n; ++i) {
          const Contact& k = contacts[static_cast<std::size_t>(i)];
          a.body1.mutable_at(i) = k.body1.index;
          a.body2.mutable_at(i) = k.body2.index;
          for (int d = 0; d < 3; ++d) {
            a.point.mutable_at(i, d) = k.point[d];
            a.normal.mutable_at(i, d) = k.normal[d];
            a.friction_impulse.mutable_at(i, d) = k.friction_impulse[d];
          }
          a.depth.mutable_at(i) = k.depth;
          a.normal_impulse.mutable_at(i) = k.normal_impulse;
        }
        return a;
      },
      "The contact points of the last step (linx.World.Contacts: arrays body1, body2, point, "
      "normal, depth, normal_impulse, friction_impulse).");
}

}  // namespace linx::python
