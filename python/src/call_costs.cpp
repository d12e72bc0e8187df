// linx._linx._read_cost: the C++ cost of reading a world's body state, measured inside the module
// on the same world and memory as the Python calls it is compared with (bench/python_overhead.py).
#include "bindings.hpp"
#include "py_world.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace py = pybind11;

namespace linx::python {

void bindCallCosts(py::module_& m) {
  m.def(
      "_read_cost",
      [](PyWorld& self, int calls, bool one_pass) {
        const World& w = self.world();
        const std::size_t n = self.bodies().size();
        std::vector<double> p(3 * n), q(4 * n), v(3 * n), s(3 * n);
        const auto t0 = std::chrono::steady_clock::now();
        for (int c = 0; c < calls; ++c) {
          // Written as a C++ program reads the state: the accessors, inline.
          if (one_pass) {  // as World.body_state()
            std::size_t i = 0;
            for (const BodyId id : self.bodies()) {
              const Body& b = w.body(id);
              std::copy_n(b.position().data(), 3, &p[3 * i]);
              const Quat& o = b.orientation();
              q[4 * i] = o.w(), q[4 * i + 1] = o.x(), q[4 * i + 2] = o.y(), q[4 * i + 3] = o.z();
              std::copy_n(b.linearVelocity().data(), 3, &v[3 * i]);
              std::copy_n(b.angularVelocity().data(), 3, &s[3 * i]);
              ++i;
            }
          } else {  // as the four properties, one after another
            std::size_t i = 0;
            for (const BodyId id : self.bodies())
              std::copy_n(w.body(id).position().data(), 3, &p[3 * i++]);
            i = 0;
            for (const BodyId id : self.bodies()) {
              const Quat& o = w.body(id).orientation();
              q[4 * i] = o.w(), q[4 * i + 1] = o.x(), q[4 * i + 2] = o.y(), q[4 * i + 3] = o.z();
              ++i;
            }
            i = 0;
            for (const BodyId id : self.bodies())
              std::copy_n(w.body(id).linearVelocity().data(), 3, &v[3 * i++]);
            i = 0;
            for (const BodyId id : self.bodies())
              std::copy_n(w.body(id).angularVelocity().data(), 3, &s[3 * i++]);
          }
          asm volatile(""
                       :
                       : "r"(p.data()), "r"(q.data()), "r"(v.data()), "r"(s.data())
                       : "memory");
        }
        const std::chrono::duration<double, std::nano> dt = std::chrono::steady_clock::now() - t0;
        return dt.count() / calls;
      },
      py::arg("world"), py::arg("calls"), py::arg("one_pass"),
      "For bench/python_overhead.py: nanoseconds per read of the whole body state in C++, into "
      "preallocated buffers, in one pass (body_state) or a pass per field (the properties).");
}

}  // namespace linx::python
