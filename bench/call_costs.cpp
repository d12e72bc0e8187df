// linx-call-costs: the C++ side of bench/python_overhead.py. Prints, as JSON, the median time
// (ns) of one World::step() of the pendulum scene in a C++ loop, and of reading the state of
// 1,000 bodies (positions, orientations, linear and angular velocities) into arrays, so that the
// Python benchmark can report what its calls add to the same work.
// Usage: linx-call-costs PENDULUM.json
#include <linx/scene.hpp>
#include <linx/world.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

template <typename Work>
double medianNs(int repeats, int calls, Work&& work) {
  std::vector<double> per_call;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    for (int i = 0; i < calls; ++i) work();
    const std::chrono::duration<double, std::nano> dt = Clock::now() - t0;
    per_call.push_back(dt.count() / calls);
  }
  std::nth_element(per_call.begin(), per_call.begin() + repeats / 2, per_call.end());
  return per_call[static_cast<std::size_t>(repeats / 2)];
}

// 1,000 free spheres, 1 m apart on a grid (bench/python_overhead.py builds the same).
linx::World thousandBodies() {
  linx::World world;
  for (int i = 0; i < 1000; ++i) {
    linx::BodyDef def;
    def.name = fmt::format("b{}", i);
    def.mass = 1.0;
    def.position = linx::Vec3(i % 10, (i / 10) % 10, i / 100);
    def.shapes.push_back(linx::ShapeDef{.type = linx::ShapeType::Sphere, .radius = 0.1});
    world.createBody(def);
  }
  return world;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: linx-call-costs PENDULUM.json\n");
    return 2;
  }
  try {
    linx::World pendulum = linx::buildWorld(linx::loadScene(argv[1]));
    const double step = medianNs(15, 20000, [&] { pendulum.step(); });

    linx::World world = thousandBodies();
    const std::vector<linx::BodyId> ids = world.bodyIds();
    std::vector<double> p(3 * ids.size()), q(4 * ids.size()), v(3 * ids.size()),
        w(3 * ids.size());
    const double read = medianNs(15, 2000, [&] {
      std::size_t i = 0;
      for (const linx::BodyId id : ids) {
        const linx::Body& b = world.body(id);
        std::copy_n(b.position().data(), 3, &p[3 * i]);
        const linx::Quat& o = b.orientation();
        q[4 * i] = o.w(), q[4 * i + 1] = o.x(), q[4 * i + 2] = o.y(), q[4 * i + 3] = o.z();
        std::copy_n(b.linearVelocity().data(), 3, &v[3 * i]);
        std::copy_n(b.angularVelocity().data(), 3, &w[3 * i]);
        ++i;
      }
      asm volatile("" : : "r"(p.data()), "r"(q.data()), "r"(v.data()), "r"(w.data()) : "memory");
    });
    std::printf("{\"step_ns\": %.1f, \"read_1000_ns\": %.1f}\n", step, read);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "linx-call-costs: %s\n", e.what());
    return 1;
  }
}
