// Runs one engine variant on one scene: builds it, times every step, samples the accuracy figure
// and the heap between steps.
#pragma once

#include "engine.hpp"
#include "scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace bench {

struct Result {
  std::string scene, size, engine, settings;
  std::string knob;        ///< Variant::knob (the Pareto table's label)
  std::string metric;      ///< what `accuracy` measures: "largest box displacement", ...
  bool is_linx = false;    ///< a row of linx (any settings)
  bool reference = false;  ///< the linx row the ratios are taken against
  bool ran = false;        ///< false: the variant refused the scene or failed (see note)
  std::string note;        ///< why it did not run, or that it stopped at the time budget
  int steps = 0;           ///< steps actually taken
  int steps_planned = 0;
  double median_ms = 0.0;  ///< median wall time of one step (ms)
  double mean_ms = 0.0;    ///< all the steps' wall time over their number (ms)
  double build_s = 0.0;    ///< wall time to build the scene (s)
  double accuracy = 0.0;   ///< the scene's metric, worst over the run
  /// false: the row has no accuracy figure (a model file's: model_files.hpp)
  bool has_accuracy = true;
  /// Scene::energy: the energy figures (Energy::rise() and end(), percent of the energy
  /// exchanged), sampled with the accuracy; NaN when the engine blew up or gives no velocities.
  bool has_energy = false;
  double energy_rise = 0.0, energy_end = 0.0;
  double energy_drift = 0.0;  ///< Energy::drift()
  /// Accuracy::joints() and Accuracy::pathPoints().
  double joints = 0.0;
  int path_points = 0;
  double heap_peak_mib = 0.0;  ///< largest heap in use during the run, less the heap before it
  /// The heap after the first step and the contact points then, and the contact points when the
  /// peak was seen: two points that split the heap into a part per body and a part per contact.
  double heap_first_mib = 0.0;
  std::size_t contacts_first = 0, contacts_at_peak = 0;
  int bodies = 0;
  int threads = 1;
  std::string one_thread;  ///< the one-thread row a row on more threads is checked against
  /// linx rows: a hash of every body's pose after each step, to compare thread counts.
  std::vector<std::uint64_t> fingerprints;
};

/// The heap in use (bytes): what malloc handed out and has not had back.
double heapInUse();

/// Runs `variant` on `scene` for scene.steps steps, or until `budget_s` seconds of stepping have
/// passed (then Result::note says so).
Result run(const Scene& scene, const Variant& variant, double budget_s);

}  // namespace bench
