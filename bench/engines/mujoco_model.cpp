// MuJoCo running an MJCF file as it is: mj_loadXML from the file itself, mj_makeData, then mj_step
// with every control at zero (mj_makeData's), the file's step and options. Built only where
// MuJoCo was found at configure time (peers_absent.cpp stands in otherwise).
#include "../model_engine.hpp"

#include <mujoco/mujoco.h>

#include <fmt/format.h>

#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace bench {
namespace {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

/// MuJoCo's default handlers print to stdout (and MUJOCO_LOG.TXT); its error handler then waits
/// for Enter and exits. Warnings go to stderr, errors become exceptions, as in mujoco_engine.cpp.
void warningToStderr(const char* message) {
  std::fprintf(stderr, "MuJoCo warning: %s\n", message);
}
[[noreturn]] void errorToException(const char* message) {
  throw std::runtime_error(std::string("MuJoCo error: ") + message);
}

const char* solverName(int solver) {
  return solver == mjSOL_NEWTON ? "Newton" : solver == mjSOL_CG ? "CG" : "PGS";
}
const char* integratorName(int integrator) {
  return integrator == mjINT_EULER ? "Euler" : integrator == mjINT_RK4 ? "RK4" : "implicit";
}

class MujocoModel final : public ModelEngine {
 public:
  explicit MujocoModel(const std::filesystem::path& path) {
    mju_user_warning = warningToStderr;
    mju_user_error = errorToException;
    char error[1000] = "";
    model_.reset(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
    if (!model_) throw CannotLoad(error);
    data_.reset(mj_makeData(model_.get()));
    if (!data_) throw std::runtime_error("mj_makeData failed");
  }

  void step() override {
    mjData* d = data_.get();
    mj_step(model_.get(), d);
    // A diverged simulation is reset by MuJoCo and goes on: the figures read NaN from then on.
    // Contacts or rows beyond the file's preallocated arrays would be dropped: the run fails.
    if (d->warning[mjWARN_BADQACC].number + d->warning[mjWARN_BADQVEL].number +
            d->warning[mjWARN_BADQPOS].number >
        0)
      diverged_ = true;
    if (d->warning[mjWARN_CONTACTFULL].number + d->warning[mjWARN_CNSTRFULL].number > 0)
      throw std::runtime_error(fmt::format(
          "MuJoCo ran out of the file's contacts (nconmax {}) or constraint rows (njmax {}) at "
          "t = {:g} s",
          model_->nconmax, model_->njmax, d->time));
  }
  double timestep() const override { return model_->opt.timestep; }
  std::string settings() const override {
    const mjOption& o = model_->opt;
    return fmt::format("the file's options: {} {} it tol {:g}, {} cone, {}, h {:g} s; controls 0",
                       solverName(o.solver), o.iterations, o.tolerance,
                       o.cone == mjCONE_PYRAMIDAL ? "pyramidal" : "elliptic",
                       integratorName(o.integrator), o.timestep);
  }
  // Bodies welded to the world (body_weldid 0) do not move; body 0 is the world.
  int movingBodies() const override {
    int n = 0;
    for (int i = 1; i < model_->nbody; ++i) n += model_->body_weldid[i] != 0;
    return n;
  }
  double movingMass() const override {
    double m = 0.0;
    for (int i = 1; i < model_->nbody; ++i)
      if (model_->body_weldid[i] != 0) m += model_->body_mass[i];
    return m;
  }
  // xipos is the centre of mass; after mj_step it is the start of the step's, so the positions'
  // kinematics are computed first (untimed: the next mj_step computes the same again).
  Vec3 centreOfMass(const std::string& name) const override {
    const int id = mj_name2id(model_.get(), mjOBJ_BODY, name.c_str());
    if (id < 0) throw std::runtime_error("MuJoCo: no body named '" + name + "'");
    if (diverged_) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    mj_kinematics(model_.get(), data_.get());
    const mjtNum* p = data_->xipos + 3 * id;
    return Vec3(p[0], p[1], p[2]);
  }
  std::string firstMovingBody() const override {
    for (int i = 1; i < model_->nbody; ++i) {
      if (model_->body_weldid[i] == 0) continue;
      const char* name = mj_id2name(model_.get(), mjOBJ_BODY, i);
      return name ? name : "";
    }
    return "";
  }

 private:
  std::unique_ptr<mjModel, ModelDeleter> model_;
  std::unique_ptr<mjData, DataDeleter> data_;
  bool diverged_ = false;
};

}  // namespace

std::vector<ModelVariant> mujocoModelVariants() {
  ModelVariant v;
  v.engine = "MuJoCo";
  v.settings = "the file's options; controls 0";
  v.make = [](const std::filesystem::path& path) -> std::unique_ptr<ModelEngine> {
    return std::make_unique<MujocoModel>(path);
  };
  return {v};
}

}  // namespace bench
