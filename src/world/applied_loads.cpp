#include "world/applied_loads.hpp"

#include "joints/validation.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace linx {

LoadId AppliedLoads::add(const LoadDef& def, std::span<const Body> bodies) {
  if (def.body.isWorld() || def.body.index >= static_cast<int>(bodies.size()))
    throw std::invalid_argument("body: must be a body of this world");
  const Body& body = bodies[static_cast<std::size_t>(def.body.index)];
  if (!body.isDynamic())
    throw std::invalid_argument(fmt::format("body: '{}' is {}: no force moves it", body.name(),
                                            body.isStatic() ? "static" : "kinematic"));
  if (def.point && !def.point->allFinite()) throw std::invalid_argument("point: not finite");
  for (const auto& [name, signal] :
       {std::pair{"force", &def.force}, std::pair{"torque", &def.torque}})
    for (int k = 0; k < 3; ++k)
      joints::validateSignal(signal->components[static_cast<std::size_t>(k)],
                             fmt::format("{}[{}]", name, k));
  Load load{def.body.index, def.force, def.torque, std::nullopt};
  if (def.point) load.point = body.pose().toLocal(*def.point);
  loads_.push_back(std::move(load));
  ++count_;
  return LoadId{static_cast<int>(loads_.size()) - 1};
}

void AppliedLoads::apply(std::span<Body> bodies, double time) const {
  for (const Load& load : loads_) {
    if (load.body < 0) continue;
    Body& body = bodies[static_cast<std::size_t>(load.body)];
    const Vec3 force = load.force.at(time);
    if (load.point)
      body.applyForceAtPoint(force, body.pose().toWorld(*load.point));
    else
      body.applyForce(force);
    body.applyTorque(load.torque.at(time));
  }
}

void AppliedLoads::remove(LoadId id) {
  if (id.index < 0 || id.index >= static_cast<int>(loads_.size()) ||
      loads_[static_cast<std::size_t>(id.index)].body < 0)
    throw std::out_of_range("no such load");
  loads_[static_cast<std::size_t>(id.index)].body = -1;
  --count_;
}

void AppliedLoads::removeBody(int body) {
  for (Load& load : loads_)
    if (load.body == body) {
      load.body = -1;
      --count_;
    }
}

}  // namespace linx
