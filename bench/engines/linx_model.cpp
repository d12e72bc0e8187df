// linx running an MJCF file as a user would: linx::importMjcf, then linx::buildWorld with the
// scene the importer made (the file's step and gravity, linx's default solver settings).
#include "../model_engine.hpp"

#include <linx/import.hpp>
#include <linx/scene.hpp>

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

namespace bench {
namespace {

linx::Scene import(const std::filesystem::path& path) {
  try {
    return linx::importMjcf(path);
  } catch (const linx::SceneError& e) {
    throw CannotLoad(e.what());
  }
}

linx::World build(const linx::Scene& scene) {
  try {
    return linx::buildWorld(scene);
  } catch (const linx::SceneError& e) {
    throw CannotLoad(e.what());
  }
}

class LinxModel final : public ModelEngine {
 public:
  explicit LinxModel(const std::filesystem::path& path)
      : scene_(import(path)), world_(build(scene_)) {}

  void step() override { world_.step(); }
  double timestep() const override { return world_.settings().timestep; }
  std::string settings() const override {
    const linx::SolverSettings& s = world_.settings().solver;
    return fmt::format("default: {} ({} it max); the file's h {:g} s and gravity",
                       linx::solverTypeName(s.type), s.iterations, timestep());
  }
  int movingBodies() const override {
    int n = 0;
    for (int i = 0; i < world_.bodyCount(); ++i) n += world_.body(linx::BodyId{i}).isDynamic();
    return n;
  }
  double movingMass() const override {
    double m = 0.0;
    for (int i = 0; i < world_.bodyCount(); ++i) {
      const linx::Body& b = world_.body(linx::BodyId{i});
      if (b.isDynamic()) m += b.mass();
    }
    return m;
  }
  Vec3 centreOfMass(const std::string& name) const override {  // a body's frame is its centre's
    const std::optional<linx::BodyId> id = world_.findBody(name);
    if (!id) throw std::runtime_error("linx: no body named '" + name + "'");
    return world_.body(*id).position();
  }
  std::string firstMovingBody() const override {  // the importer keeps the file's order
    for (int i = 0; i < world_.bodyCount(); ++i) {
      const linx::Body& b = world_.body(linx::BodyId{i});
      if (b.isDynamic()) return b.name();
    }
    return "";
  }

 private:
  linx::Scene scene_;
  linx::World world_;
};

}  // namespace

std::vector<ModelVariant> linxModelVariants() {
  ModelVariant v;
  v.engine = "linx";
  v.settings = "default; the file's step and gravity";
  v.make = [](const std::filesystem::path& path) -> std::unique_ptr<ModelEngine> {
    return std::make_unique<LinxModel>(path);
  };
  v.reference = true;
  return {v};
}

}  // namespace bench
