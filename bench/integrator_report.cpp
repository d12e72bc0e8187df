// The integrator table (linx-bench --integrators) and issue 19's speed target: per mechanism, each
// engine and integrator setting's cost against its error, the error measured against an
// independent truth (a closed form, a published reference solution, the conservation of energy).
#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace bench {
namespace {

// Errors below this (m, or relative energy) are round-off: equally accurate.
constexpr double kErrorFloor = 1e-12;

bool hasPath(const Result& r) {
  return r.has_accuracy && r.path_points > 0;
}

/// The figure a row is judged by: its distance from the known path where the scene has one, else
/// its energy drift relative to the energy exchanged; NaN when it did not run every step or blew up
/// (a NaN pose: the path then has no point compared, and the energy must not stand in for it).
double error(const Result& r) {
  if (!r.ran || r.steps < r.steps_planned) return NAN;
  if (r.has_accuracy && std::isnan(r.accuracy)) return NAN;
  return hasPath(r) ? r.accuracy : r.energy_drift / 100.0;
}

/// Stepping time over the run (s).
double total(const Result& r) {
  return r.mean_ms * r.steps / 1e3;
}

std::string number(double x, const char* unit) {
  if (std::isnan(x)) return "NaN";
  return fmt::format("{:.2e}{}", x, unit);
}

/// The scenes in the order they ran, each with its rows.
std::vector<std::vector<const Result*>> byScene(const std::vector<Result>& results) {
  std::vector<std::vector<const Result*>> out;
  for (const Result& r : results) {
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& rows) {
      return rows.front()->scene == r.scene && rows.front()->size == r.size;
    });
    if (it == out.end()) {
      out.push_back({&r});
    } else {
      it->push_back(&r);
    }
  }
  return out;
}

/// The target against one peer's rows (engine `engine`, knob containing `knob`; accuracy
/// sweeps, coarse to fine): the fastest row at least as accurate as linx's reference row decides.
/// When none is, linx must be faster than the finest too, unless the peer's error stopped falling
/// (the finest row no better than half the next coarser one's): then no finer setting would make
/// it as accurate.
Target againstPeer(const Result& lx, const std::vector<const Result*>& scene,
                   const std::string& engine, const std::string& knob, const std::string& peer) {
  const std::string name = lx.scene + " (" + lx.size + ")";
  const double mine = error(lx);
  const char* unit = hasPath(lx) ? " m" : " of the energy";
  std::vector<const Result*> rows;
  for (const Result* r : scene)
    if (r->engine == engine && r->knob.find(knob) != std::string::npos && !std::isnan(error(*r)))
      rows.push_back(r);
  if (rows.empty())
    return {false, false,
            fmt::format("{}: {} did not run every step (or is not built)", name, peer)};
  const auto faster = [](const Result* a, const Result* b) { return total(*a) < total(*b); };
  std::vector<const Result*> as_accurate;
  for (const Result* r : rows)
    if (error(*r) <= std::max(mine, kErrorFloor)) as_accurate.push_back(r);
  if (!as_accurate.empty()) {
    const Result& best = **std::min_element(as_accurate.begin(), as_accurate.end(), faster);
    return {total(lx) < total(best), true,
            fmt::format("{}: at equal accuracy faster than {}: linx {}, {}{} in {:.3g} s; the "
                        "fastest {} row as accurate, {}, {}{} in {:.3g} s ({:.2f} times linx's "
                        "time)",
                        name, peer, lx.knob, number(mine, ""), unit, total(lx), peer, best.knob,
                        number(error(best), ""), unit, total(best), total(best) / total(lx))};
  }
  std::sort(rows.begin(), rows.end(), faster);  // coarse to fine: time grows with accuracy
  const Result& finest = *rows.back();
  const bool stalled = rows.size() >= 2 && error(finest) > 0.5 * error(*rows[rows.size() - 2]);
  return {total(lx) <= total(finest) || stalled, true,
          fmt::format("{}: no {} row as accurate as linx {} ({}{} in {:.3g} s); its finest, {}, "
                      "{}{} in {:.3g} s ({:.2f} times linx's time){}",
                      name, peer, lx.knob, number(mine, ""), unit, total(lx), finest.knob,
                      number(error(finest), ""), unit, total(finest), total(finest) / total(lx),
                      stalled ? "; its error no longer falls as its setting tightens" : "")};
}

}  // namespace

std::string integratorTable(const std::vector<Result>& results, bool markdown) {
  std::string out;
  for (const std::vector<const Result*>& scene : byScene(results)) {
    const Result& first = *scene.front();
    std::vector<std::vector<std::string>> rows;
    for (const Result* r : scene) {
      std::string note = r->note;
      if (r->ran && r->steps < r->steps_planned)
        note = fmt::format("{} ({} of {} steps)", note, r->steps, r->steps_planned);
      const bool path = first.path_points > 0 || hasPath(*r);
      rows.push_back({r->engine, r->knob.empty() ? r->settings : r->knob,
                      r->ran ? fmt::format("{:.4g}", r->median_ms) : "-",
                      r->ran ? fmt::format("{:.3g}", total(*r)) : "-",
                      !r->ran ? "-"
                      : path  ? number(r->accuracy, " m")
                              : "",
                      r->ran ? number(r->energy_drift / 100.0, "") : "-",
                      r->ran ? number(r->joints, " m") : "-", note});
    }
    const std::string title = fmt::format(
        "{} ({}), {} steps: path error = largest distance from the known path, "
        "energy = largest |E - E0| / energy exchanged",
        first.scene, first.size, first.steps_planned);
    out += markdown ? "\n**" + title + "**\n\n" : "\n" + title + "\n";
    out += render(
        {"engine", "integrator", "ms/step (median)", "s (run)", "path error", "energy drift",
         "joints", "note"},
        rows, [](std::size_t i) { return i >= 2 && i <= 6; }, markdown);
  }
  return out;
}

std::vector<Target> integratorTargets(const std::vector<Result>& results) {
  std::vector<Target> out;
  for (const std::vector<const Result*>& scene : byScene(results)) {
    const auto linx =
        std::find_if(scene.begin(), scene.end(), [](const Result* r) { return r->reference; });
    if (linx == scene.end() || std::isnan(error(**linx))) continue;
    out.push_back(againstPeer(**linx, scene, "MuJoCo", "RK4", "MuJoCo RK4"));
    out.push_back(againstPeer(**linx, scene, "Simbody", "RK Merson", "Simbody RK Merson"));
  }
  return out;
}

}  // namespace bench
