#include "model_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace bench {
namespace {

using Clock = std::chrono::steady_clock;

// Where Debian's libmujoco-samples puts MuJoCo's humanoids.
constexpr const char* kSamples = "/usr/share/mujoco/model/humanoid";
// Two engines' masses of one file agree when they differ by less than this, relative: both
// integrate the same solids, so only round-off may part them.
constexpr double kMassTolerance = 1e-9;
// Steps between two samples of the heap (outside the timed steps).
constexpr int kHeapEvery = 16;

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

int plannedSteps(const ModelSchedule& schedule, double h) {
  const int steps = std::max(1, static_cast<int>(std::lround(schedule.duration / h)));
  return schedule.max_steps > 0 ? std::min(steps, schedule.max_steps) : steps;
}

/// An engine's message on one line (MuJoCo's name the element on a second one).
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at))
    text.replace(at, 1, at > 0 && text[at - 1] == '.' ? " " : "; ");
  return text;
}

std::string vec(const Vec3& v) {
  return fmt::format("({:.4f}, {:.4f}, {:.4f})", v.x(), v.y(), v.z());
}

/// "MuJoCo: 16 moving bodies, 40.844 kg; torso's centre of mass at t = 2 s: (x, y, z) m".
std::string figuresText(const ModelFigures& f) {
  if (!f.refused.empty()) return fmt::format("{}: {}", f.engine, f.refused);
  return fmt::format("{}: {} moving bodies, {:.6g} kg; {}'s centre of mass at t = {:g} s: {} m",
                     f.engine, f.bodies, f.mass, f.body, f.time, vec(f.com));
}

/// A peer's figures against linx's: the masses (which must agree) and the body's height.
std::string againstText(const ModelFigures& lx, const ModelFigures& peer) {
  const double relative = (lx.mass - peer.mass) / peer.mass;
  const std::string mass =
      std::abs(relative) < kMassTolerance
          ? fmt::format("masses agree (relative difference {:.1e})", relative)
          : fmt::format("masses DIFFER: {:.6g} kg against {:.6g} kg (relative {:+.2e})", lx.mass,
                        peer.mass, relative);
  const std::string body =
      lx.body == peer.body ? lx.body : fmt::format("{} (against {})", lx.body, peer.body);
  std::string height = fmt::format("{}'s height {:.4f} m against {:.4f} m ({:+.2e} m)", body,
                                   lx.com.z(), peer.com.z(), lx.com.z() - peer.com.z());
  if (lx.time != peer.time)
    height += fmt::format(" at t = {:g} s against {:g} s", lx.time, peer.time);
  return fmt::format("linx against {}: {}; {}", peer.engine, mass, height);
}

}  // namespace

std::vector<ModelCase> modelCases() {
  const std::filesystem::path samples = kSamples;
  const std::string debian = "Debian package libmujoco-samples";
  return {
      {"humanoid", samples / "humanoid.xml", "torso", 16, debian},
      {"22_humanoids", samples / "22_humanoids.xml", "1a_torso", 22 * 16, debian},
      {"four_bar", std::filesystem::path(LINX_BENCH_EXAMPLES_DIR) / "robots" / "four_bar.xml",
       "coupler", 3, "linx's examples/robots"},
  };
}

ModelCase modelCase(const std::filesystem::path& path) {
  return {path.stem().string(), path, "", 0, "the command line"};
}

ModelRun runModel(const ModelCase& model, const ModelVariant& variant,
                  const ModelSchedule& schedule, double budget_s) {
  ModelRun out;
  Result& r = out.result;
  r.scene = model.key;
  r.size = model.path.filename().string();
  r.engine = variant.engine;
  r.settings = variant.settings;
  r.is_linx = variant.engine == "linx";
  r.reference = variant.reference;
  r.has_accuracy = false;
  r.bodies = model.bodies;
  ModelFigures& f = out.figures;
  f.scene = r.scene;
  f.file = r.size;
  f.engine = r.engine;
  try {
    std::vector<double> ms;
    double stepping = 0.0, heap_peak = 0.0;
    int runs = 0;
    for (; runs < schedule.runs && (runs == 0 || stepping <= budget_s); ++runs) {
      const double heap0 = heapInUse();
      const auto t0 = Clock::now();
      std::unique_ptr<ModelEngine> engine = variant.make(model.path);
      const double build_s = seconds(Clock::now() - t0);
      const int steps = plannedSteps(schedule, engine->timestep());
      int taken = 0;
      while (taken < steps && (taken == 0 || stepping <= budget_s)) {
        const auto a = Clock::now();
        engine->step();
        const double dt = seconds(Clock::now() - a);
        ms.push_back(1e3 * dt);
        stepping += dt;
        ++taken;
        if (taken % kHeapEvery == 0 || taken == steps)
          heap_peak = std::max(heap_peak, heapInUse() - heap0);
      }
      if (runs == 0) {
        r.build_s = build_s;
        r.settings = engine->settings();
        r.steps = taken;
        r.steps_planned = steps;
        f.bodies = engine->movingBodies();
        f.mass = engine->movingMass();
        f.time = taken * engine->timestep();
        f.body = model.body.empty() ? engine->firstMovingBody() : model.body;
        f.com = engine->centreOfMass(f.body);
      }
    }
    const double total_ms = 1e3 * stepping;
    std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
    r.median_ms = ms[ms.size() / 2];
    r.mean_ms = total_ms / static_cast<double>(ms.size());
    r.heap_peak_mib = heap_peak / (1024.0 * 1024.0);
    if (r.steps < r.steps_planned)
      r.note = fmt::format("stopped at the {} s budget", static_cast<int>(budget_s));
    else if (runs < schedule.runs)
      r.note = fmt::format("{} of {} runs (the {} s budget)", runs, schedule.runs,
                           static_cast<int>(budget_s));
    r.ran = true;
  } catch (const CannotLoad& e) {
    r.note = "cannot load: " + oneLine(e.what());
    r.reference = false;  // a file linx does not read yet is no failure of the benchmark
    f.refused = r.note;
  } catch (const std::exception& e) {
    r.note = "failed: " + oneLine(e.what());
    f.refused = r.note;
  }
  return out;
}

std::string modelLines(const std::vector<ModelFigures>& figures,
                       const std::vector<std::string>& skipped, bool markdown) {
  std::vector<std::string> lines;
  std::vector<std::string> done;  // files in the order they ran
  for (const ModelFigures& first : figures) {
    if (std::find(done.begin(), done.end(), first.scene) != done.end()) continue;
    done.push_back(first.scene);
    const ModelFigures* lx = nullptr;
    for (const ModelFigures& f : figures) {
      if (f.scene != first.scene) continue;
      lines.push_back(fmt::format("{} ({}), {}", f.scene, f.file, figuresText(f)));
      if (f.engine == "linx" && f.refused.empty()) lx = &f;
    }
    for (const ModelFigures& f : figures) {
      if (lx && f.scene == first.scene && f.engine != "linx" && f.refused.empty())
        lines.push_back(fmt::format("{} ({}), {}", f.scene, f.file, againstText(*lx, f)));
    }
  }
  for (const std::string& s : skipped) lines.push_back(s);
  if (lines.empty()) return "";
  std::string out =
      "Model files (each engine reads the file itself; controls 0; the named body's centre of "
      "mass at the end):\n";
  if (markdown) out += "\n";
  for (const std::string& l : lines) out += (markdown ? "- " : "") + l + "\n";
  return out;
}

}  // namespace bench
