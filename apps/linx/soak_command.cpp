// `linx soak`: the memory of a world stepped for a long time. Memory is measured two ways: the
// heap in use (glibc's mallinfo2: what the engine holds, the figure a leak moves) and the
// process's resident set (/proc/self/statm: what the machine gives it). Warm-up is the first half
// of the steps: buffers grow to their working size, which takes as long as the bodies keep finding
// arrangements with more rows than before (a chain folding onto itself: 10 s); after it, the heap
// must stay within max_growth of its value at the end of warm-up (a leak grows in both halves).
#include "soak_command.hpp"

#include "cli_common.hpp"
#include "stop_signals.hpp"

#include <linx/linx.hpp>

#include <fmt/format.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

namespace linx::cli {

namespace {

struct Memory {
  double heap_mib = 0.0;      // malloc'd and in use
  double resident_mib = 0.0;  // resident set
};

Memory memoryNow() {
  Memory m;
  const struct mallinfo2 info = mallinfo2();
  m.heap_mib = static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  if (statm >> pages >> resident)
    m.resident_mib = static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) /
                     (1024.0 * 1024.0);
  return m;
}

}  // namespace

void addSoakOptions(CLI::App& cmd, SoakOptions& options) {
  cmd.add_option("scenes", options.scenes, "Scenes to step (a contact scene and a jointed one)")
      ->required();
  cmd.add_option("--steps", options.steps, "Steps of each scene")->capture_default_str();
  cmd.add_option("--report-every", options.report_every, "Steps between memory reports")
      ->capture_default_str();
  cmd.add_option("--max-growth", options.max_growth,
                 "Heap growth after warm-up (fraction) above which the soak fails")
      ->capture_default_str();
}

int soak(const SoakOptions& options) {
  if (options.steps < 10)
    throw BadInput(fmt::format("--steps: must be at least 10, got {}", options.steps));
  if (options.report_every < 1)
    throw BadInput(fmt::format("--report-every: must be at least 1, got {}", options.report_every));
  if (!(options.max_growth >= 0))
    throw BadInput(fmt::format("--max-growth: must be >= 0, got {}", options.max_growth));
  // Every scene is loaded first: a bad one is refused before hours of stepping.
  std::vector<Scene> scenes;
  for (const std::string& file : options.scenes)
    whileLoading(file, [&] { scenes.push_back(loadModel(file)); });
  const StopSignals stop_signals;
  int status = 0;
  const std::int64_t warm_up = std::max<std::int64_t>(1, options.steps / 2);
  for (Scene& scene : scenes) {
    scene.settings.sleep.enabled = false;  // every step does its work
    World world = buildWorld(scene);
    say("{}: {} bodies, {} joints, {} steps of {} s (sleep off)\n", scene.file, scene.bodies.size(),
        scene.joints.size(), options.steps, scene.settings.timestep);
    say("{:>10}  {:>12}  {:>9}  {:>9}  {:>9}\n", "step", "t (s)", "heap MiB", "RSS MiB", "ms/step");
    double warm_heap = 0.0, peak_heap = 0.0;
    auto since = std::chrono::steady_clock::now();
    std::int64_t since_step = 0;
    const auto report = [&](std::int64_t step) {
      const Memory m = memoryNow();
      const auto now = std::chrono::steady_clock::now();
      const double ms = step > since_step
                            ? std::chrono::duration<double, std::milli>(now - since).count() /
                                  static_cast<double>(step - since_step)
                            : 0.0;
      say("{:>10}  {:>12.6g}  {:>9.3f}  {:>9.1f}  {:>9.4f}\n", step, world.time(), m.heap_mib,
          m.resident_mib, ms);
      std::fflush(stdout);
      since = now;
      since_step = step;
      return m;
    };
    report(0);
    for (std::int64_t step = 1; step <= options.steps; ++step) {
      try {
        world.step();
      } catch (const StepFault& e) {
        say(stderr, "linx: soak: {}: {}\n", scene.file, e.what());
        status = kExitNonFinite;
        break;
      }
      if (StopSignals::received()) {
        say(stderr, "linx: soak: interrupted at step {} of {}\n", step, scene.file);
        return kExitInterrupted;
      }
      const bool warm = step == warm_up;
      if (step % options.report_every == 0 || step == options.steps || warm) {
        const Memory m = report(step);
        if (warm) warm_heap = m.heap_mib;
        if (step > warm_up) peak_heap = std::max(peak_heap, m.heap_mib);
      }
      if (step == options.steps) {
        const double growth = warm_heap > 0 ? (peak_heap - warm_heap) / warm_heap : 0.0;
        const bool flat = growth <= options.max_growth;
        say("{}: heap {:.3f} MiB after warm-up (step {}), at most {:.3f} MiB after: {:+.2f} "
            "% ({})\n",
            scene.file, warm_heap, warm_up, peak_heap, 100.0 * growth, flat ? "flat" : "GREW");
        if (!flat && status == 0) status = kExitFailure;
      }
    }
  }
  return status;
}

}  // namespace linx::cli
