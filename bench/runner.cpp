#include "runner.hpp"

#include "metrics.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

namespace bench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

/// FNV-1a over the bits of every pose: equal only if every coordinate is equal to the bit.
std::uint64_t fingerprint(const Engine& engine, int bodies) {
  std::uint64_t h = 14695981039346656037u;
  const auto mix = [&](double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    for (int k = 0; k < 8; ++k) {
      h ^= (bits >> (8 * k)) & 0xffu;
      h *= 1099511628211u;
    }
  };
  for (int i = 0; i < bodies; ++i) {
    const Pose p = engine.pose(i);
    for (int k = 0; k < 3; ++k) mix(p.position[k]);
    for (int k = 0; k < 4; ++k) mix(p.orientation.coeffs()[k]);
  }
  return h;
}

}  // namespace

double heapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}

Result run(const Scene& scene, const Variant& variant, double budget_s) {
  Result r;
  r.scene = scene.name;
  r.size = scene.size;
  r.engine = variant.engine;
  r.settings = variant.settings;
  r.knob = variant.knob;
  r.metric = Accuracy::describe(scene.metric);
  r.is_linx = variant.engine == "linx";
  r.reference = variant.reference;
  r.steps_planned = scene.steps;
  r.bodies = static_cast<int>(scene.bodies.size());
  r.threads = variant.threads;
  r.one_thread = variant.one_thread;
  try {
    const double heap0 = heapInUse();
    double heap_peak = heap0;
    const auto t0 = Clock::now();
    std::unique_ptr<Engine> engine = variant.make(scene);
    r.build_s = seconds(Clock::now() - t0);
    heap_peak = std::max(heap_peak, heapInUse());

    Accuracy accuracy(scene);
    Energy energy(scene);
    std::vector<double> ms;
    ms.reserve(static_cast<std::size_t>(scene.steps));
    r.fingerprints.reserve(static_cast<std::size_t>(scene.steps));
    double stepping = 0.0;
    for (int s = 1; s <= scene.steps; ++s) {
      const auto a = Clock::now();
      engine->step();
      const double dt = seconds(Clock::now() - a);
      ms.push_back(1e3 * dt);
      stepping += dt;
      if (r.is_linx) r.fingerprints.push_back(fingerprint(*engine, r.bodies));
      if (s == 1) {  // the heap's first sample after a step (the accuracy keeps its schedule)
        const double heap = heapInUse();
        r.heap_first_mib = (heap - heap0) / (1024.0 * 1024.0);
        r.contacts_first = engine->contactCount();
        if (heap > heap_peak) {
          heap_peak = heap;
          r.contacts_at_peak = r.contacts_first;
        }
      }
      if (accuracy.due(s) || stepping > budget_s) {
        accuracy.sample(*engine, s * scene.timestep);
        if (scene.energy) energy.sample(*engine);
        const double heap = heapInUse();
        if (heap > heap_peak) {
          heap_peak = heap;
          r.contacts_at_peak = engine->contactCount();
        }
      }
      if (stepping > budget_s && s < scene.steps) {
        r.note = "stopped at the " + std::to_string(static_cast<int>(budget_s)) + " s budget";
        break;
      }
    }
    r.steps = static_cast<int>(ms.size());
    std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
    r.median_ms = ms[ms.size() / 2];
    r.mean_ms = 1e3 * stepping / static_cast<double>(ms.size());
    r.accuracy = accuracy.value();
    r.has_energy = scene.energy;
    r.energy_rise = energy.rise();
    r.energy_end = energy.end();
    r.energy_drift = energy.drift();
    r.joints = accuracy.joints();
    r.path_points = accuracy.pathPoints();
    r.heap_peak_mib = (heap_peak - heap0) / (1024.0 * 1024.0);
    r.ran = true;
    engine.reset();
  } catch (const Unsupported& e) {
    r.note = e.what();
  } catch (const std::exception& e) {
    r.note = std::string("failed: ") + e.what();
  }
  return r;
}

}  // namespace bench
