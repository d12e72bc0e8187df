#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <thread>

namespace bench {
namespace {

// Accuracy figures below this are round-off: two engines under it are equally accurate.
constexpr double kAccuracyFloor = 1e-9;

std::string accuracyText(const Result& r) {
  if (!r.has_accuracy) return "";
  if (!r.ran) return "-";
  if (std::isnan(r.accuracy)) return "NaN";
  return fmt::format("{:.2e} m", r.accuracy);
}

/// The energy figures of a chain row: "+0.0 % / -5.9 %" (the largest rise / the change at the
/// end, percent of the energy exchanged); empty for scenes without them.
std::string energyText(const Result& r) {
  if (!r.has_energy) return "";
  if (!r.ran) return "-";
  if (std::isnan(r.energy_rise) || std::isnan(r.energy_end)) return "NaN";
  return fmt::format("{:+.1f} % / {:+.1f} %", r.energy_rise, r.energy_end);
}

bool asAccurate(double a, double b) {  // a at least as good as b
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  return a <= std::max(b, kAccuracyFloor);
}

const Result* linxOf(const std::vector<Result>& results, const Result& r) {
  for (const Result& x : results) {
    if (x.reference && x.ran && x.scene == r.scene && x.size == r.size) return &x;
  }
  return nullptr;
}

std::string firstLine(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

}  // namespace

std::string render(const std::vector<std::string>& head,
                   const std::vector<std::vector<std::string>>& rows,
                   const std::function<bool(std::size_t)>& right, bool markdown) {
  std::string out;
  if (markdown) {
    const auto line = [&](const std::vector<std::string>& cells) {
      out += "|";
      for (const std::string& c : cells) out += " " + c + " |";
      out += "\n";
    };
    line(head);
    out += "|";
    for (std::size_t i = 0; i < head.size(); ++i) out += right(i) ? "---:|" : "---|";
    out += "\n";
    for (const auto& row : rows) line(row);
    return out;
  }
  std::vector<std::size_t> width(head.size());
  for (std::size_t i = 0; i < head.size(); ++i) width[i] = head[i].size();
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
  }
  const auto line = [&](const std::vector<std::string>& cells) {
    std::string l;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      l += right(i) ? fmt::format("{:>{}}", cells[i], width[i])
                    : fmt::format("{:<{}}", cells[i], width[i]);
      l += i + 1 < cells.size() ? "  " : "";
    }
    while (!l.empty() && l.back() == ' ') l.pop_back();
    out += l + "\n";
  };
  line(head);
  for (const auto& row : rows) line(row);
  return out;
}

std::vector<std::string> machineDescription() {
  char date[32] = "";
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return {fmt::format("CPU: {} ({} hardware threads)", firstLine("/proc/cpuinfo", "model name"),
                      std::thread::hardware_concurrency()),
          fmt::format("Memory: {}", firstLine("/proc/meminfo", "MemTotal")),
          fmt::format("Compiler: GCC {}.{}.{}, {}", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__,
#ifdef NDEBUG
                      "optimized (NDEBUG)"
#else
                      "assertions on: not a release build"
#endif
                      ),
          fmt::format("Date: {}", date)};
}

std::string table(const std::vector<Result>& results, bool markdown) {
  const std::vector<std::string> head = {"scene",    "size",   "engine",      "settings", "ms/step",
                                         "accuracy", "energy", "time / linx", "heap MiB", "note"};
  std::vector<std::vector<std::string>> rows;
  for (const Result& r : results) {
    const Result* lx = linxOf(results, r);
    std::string ratio = "-";
    if (r.ran && lx && lx->median_ms > 0)
      ratio = fmt::format("{:.2f}", r.median_ms / lx->median_ms);
    std::string note = r.note;
    if (r.ran && r.steps < r.steps_planned) {
      note = fmt::format("{} ({} of {} steps)", note, r.steps, r.steps_planned);
    }
    rows.push_back({r.scene, r.size, r.engine, r.settings,
                    r.ran ? fmt::format("{:.4g}", r.median_ms) : "-", accuracyText(r),
                    energyText(r), ratio, r.ran ? fmt::format("{:.1f}", r.heap_peak_mib) : "-",
                    note});
  }
  return render(
      head, rows, [](std::size_t i) { return i >= 4 && i <= 8; }, markdown);
}

std::string paretoTable(const std::vector<Result>& results, bool markdown) {
  // A row takes part when it ran every step to a finite figure; figures below the floor are equal.
  const auto complete = [](const Result& r) {
    return r.ran && r.steps == r.steps_planned && !std::isnan(r.accuracy);
  };
  const auto error = [](const Result& r) { return std::max(r.accuracy, kAccuracyFloor); };
  const auto dominates = [&](const Result& a,
                             const Result& b) {  // a at least as good, better in one
    return a.median_ms <= b.median_ms && error(a) <= error(b) &&
           (a.median_ms < b.median_ms || error(a) < error(b));
  };
  std::string out;
  std::vector<std::string> done;  // scenes in the order they ran
  for (const Result& first : results) {
    const std::string key = first.scene + " " + first.size;
    if (std::find(done.begin(), done.end(), key) != done.end()) continue;
    done.push_back(key);
    std::vector<const Result*> scene;
    for (const Result& r : results) {
      if (r.scene == first.scene && r.size == first.size) scene.push_back(&r);
    }
    // The complete rows by time, so that the front reads down the table; the others after them.
    std::stable_sort(scene.begin(), scene.end(), [&](const Result* a, const Result* b) {
      if (complete(*a) != complete(*b)) return complete(*a);
      return complete(*a) && a->median_ms < b->median_ms;
    });
    std::vector<std::vector<std::string>> rows;
    for (const Result* r : scene) {
      std::string front = "-";
      if (complete(*r)) {
        front = "yes";
        for (const Result* other : scene) {
          if (complete(*other) && dominates(*other, *r)) front = "";
        }
      }
      std::string note = r->note;
      if (r->ran && r->steps < r->steps_planned) {
        note = fmt::format("{} ({} of {} steps: off the front)", note, r->steps, r->steps_planned);
      }
      rows.push_back({r->engine, r->knob.empty() ? r->settings : r->knob,
                      r->ran ? fmt::format("{:.4g}", r->median_ms) : "-",
                      r->ran ? fmt::format("{:.4g}", r->mean_ms) : "-", accuracyText(*r), front,
                      note});
    }
    const std::string title =
        fmt::format("{}, accuracy: {} (worst over the run)", key, first.metric);
    out += markdown ? "\n**" + title + "**\n\n" : "\n" + title + "\n";
    out += render(
        {"engine", "settings (the swept count)", "ms/step (median)", "mean", "accuracy",
         "Pareto front", "note"},
        rows, [](std::size_t i) { return i >= 2 && i <= 4; }, markdown);
  }
  return out;
}

std::vector<Target> targets(const std::vector<Result>& results) {
  std::vector<Target> out;
  // Every linx row is judged, each with its settings.
  std::map<std::string, const Result*> linx_by_key;
  for (const Result& r : results) {
    if (r.is_linx && r.ran && r.has_accuracy)
      linx_by_key[r.scene + " " + r.size + ", linx " + r.settings] = &r;
  }
  for (const auto& [key, lx] : linx_by_key) {
    if (lx->steps < lx->steps_planned) {
      out.push_back({false, true, fmt::format("{}: linx did not finish ({})", key, lx->note)});
      continue;
    }
    const Result* fastest = nullptr;   // fastest peer at least as accurate as linx
    const Result* accurate = nullptr;  // most accurate peer
    int peers = 0;
    for (const Result& r : results) {
      if (r.is_linx || !r.ran || !r.has_accuracy || r.scene != lx->scene || r.size != lx->size)
        continue;
      if (r.steps < r.steps_planned) continue;  // a partial run is no comparison
      ++peers;
      if (asAccurate(r.accuracy, lx->accuracy) && (!fastest || r.median_ms < fastest->median_ms)) {
        fastest = &r;
      }
      if (!accurate || asAccurate(r.accuracy, accurate->accuracy)) {
        if (!accurate || r.accuracy < accurate->accuracy) accurate = &r;
      }
    }
    if (peers == 0) continue;
    if (fastest) {
      const bool met = lx->median_ms <= 0.5 * fastest->median_ms;
      out.push_back(
          {met, true,
           fmt::format("{}: time {:.4g} ms vs half of {:.4g} ms ({} {}), the fastest peer "
                       "as accurate",
                       key, lx->median_ms, fastest->median_ms, fastest->engine,
                       fastest->settings)});
    } else {
      out.push_back({true, true,
                     fmt::format("{}: time {:.4g} ms; no peer is as accurate, so none to halve",
                                 key, lx->median_ms)});
    }
    if (accurate) {
      const bool met = asAccurate(lx->accuracy, accurate->accuracy);
      out.push_back({met, true,
                     fmt::format("{}: accuracy {} vs {} ({} {}), the most accurate peer", key,
                                 accuracyText(*lx), accuracyText(*accurate), accurate->engine,
                                 accurate->settings)});
    }
  }
  // Scene-specific targets.
  for (const auto& [key, lx] : linx_by_key) {
    if (lx->scene == "chain" || lx->scene == "heavy chain") {
      out.push_back({lx->accuracy < 1e-4, true,
                     fmt::format("{}: joint separation {} below 1e-4 m", key, accuracyText(*lx))});
    }
    if (lx->scene == "heavy chain" && lx->reference && lx->has_energy) {
      // The "energy never above its start by more than 1 % of the energy exchanged".
      const bool finished = lx->steps == lx->steps_planned;
      std::string text =
          fmt::format("{}: energy rise {} of the energy exchanged vs 1 %", key,
                      std::isnan(lx->energy_rise) ? std::string("NaN")
                                                  : fmt::format("{:.3g} %", lx->energy_rise));
      if (!finished)
        text +=
            fmt::format(" (after only {} of {} steps: the budget)", lx->steps, lx->steps_planned);
      out.push_back({finished && lx->energy_rise <= 1.0, true, std::move(text)});
    }
    if (lx->scene == "pyramid") {
      out.push_back(
          {lx->accuracy < 0.01 && lx->steps == lx->steps_planned, true,
           lx->steps == lx->steps_planned
               ? fmt::format("{}: every box within 1 cm after 10 s: {}", key, accuracyText(*lx))
               : fmt::format("{}: every box within 1 cm after 10 s: {} after only {} of {} steps "
                             "(the budget)",
                             key, accuracyText(*lx), lx->steps, lx->steps_planned)});
    }
  }
  for (const char* chain : {"chain", "heavy chain"}) {
    for (const auto& [key, small] : linx_by_key) {
      if (small->scene != chain || small->size != "N=100") continue;
      const auto big = linx_by_key.find(std::string(chain) + " N=1000, linx " + small->settings);
      if (big == linx_by_key.end()) continue;
      const double ratio = big->second->median_ms / small->median_ms;
      out.push_back({ratio <= 12.0, true,
                     fmt::format("{}, linx {}: time(N=1000) / time(N=100) = {:.1f}, at most 12",
                                 chain, small->settings, ratio)});
    }
  }
  for (const auto& [key, lx] : linx_by_key) {
    if (lx->scene != "spheres" || lx->size != "N=64000" || !lx->reference) continue;
    // Two samples of the heap, after the first step and at the peak, split it into a part per
    // body and a part per contact point: heap = bodies * b + contacts * c. Everything the heap
    // gains after the first step is charged to the contacts (their rows, the broadphase's pairs,
    // the vectors' growth slack); without that growth the split is impossible and the peak
    // itself, contacts included, is held to 1 KiB per body.
    const double mib = 1024.0 * 1024.0;
    const double bodies = lx->bodies;
    const double peak = lx->heap_peak_mib * mib;
    const double grown =
        static_cast<double>(lx->contacts_at_peak) - static_cast<double>(lx->contacts_first);
    if (grown <= 0.0 || lx->heap_peak_mib <= lx->heap_first_mib) {
      out.push_back({peak / bodies <= 1024.0, true,
                     fmt::format("{}: peak heap {:.1f} MiB, {:.0f} bytes per body with the "
                                 "contacts (no growth of contacts to split them off), below 1 KiB",
                                 key, lx->heap_peak_mib, peak / bodies)});
      continue;
    }
    const double per_contact = (peak - lx->heap_first_mib * mib) / grown;
    const double per_body =
        (lx->heap_first_mib * mib - per_contact * static_cast<double>(lx->contacts_first)) / bodies;
    out.push_back({per_body >= 0.0 && per_body <= 1024.0, true,
                   fmt::format("{}: peak heap {:.1f} MiB with {} contact points, {:.1f} MiB after "
                               "the first step with {}: {:.0f} bytes per body and {:.0f} per "
                               "contact point (all growth after the first step charged to the "
                               "contacts); below 1 KiB per body plus the contacts",
                               key, lx->heap_peak_mib, lx->contacts_at_peak, lx->heap_first_mib,
                               lx->contacts_first, per_body, per_contact)});
  }
  // Threads: a row on several threads against the one-thread row of its scene.
  for (const Result& many : results) {
    if (!many.is_linx || many.threads <= 1 || !many.ran) continue;
    const Result* one = linxOf(results, many);
    if (!many.one_thread.empty()) {
      one = nullptr;
      for (const Result& x : results)
        if (x.ran && x.is_linx && x.scene == many.scene && x.size == many.size &&
            x.settings == many.one_thread)
          one = &x;
    }
    if (!one || one->threads != 1) continue;
    const std::size_t common = std::min(one->fingerprints.size(), many.fingerprints.size());
    std::size_t same = 0;
    while (same < common && one->fingerprints[same] == many.fingerprints[same]) ++same;
    const bool identical = common > 0 && same == common;
    const double speedup = one->median_ms / many.median_ms;
    const std::string key =
        many.scene + " " + many.size + (many.one_thread.empty() ? "" : " (" + one->settings + ")");
    const std::string what = identical
                                 ? fmt::format("identical poses over all {} steps both ran", common)
                                 : fmt::format("poses differ from step {}", same + 1);
    if (many.scene == "spheres" && many.size == "N=64000" && many.one_thread.empty())
      out.push_back({speedup >= 1.7 && identical, true,
                     fmt::format("{}, linx on {} threads: {:.2f} times as fast as on one, at "
                                 "least 1.7; {}",
                                 key, many.threads, speedup, what)});
    else
      out.push_back({identical, true,
                     fmt::format("{}, linx on {} threads: {}; {:.2f} times as fast as on one", key,
                                 many.threads, what, speedup)});
  }
  return out;
}

std::string targetLines(const std::vector<Target>& targets, bool markdown) {
  std::string out;
  for (const Target& t : targets) {
    const char* mark = !t.measured ? "not measured" : t.met ? "met" : "NOT MET";
    out += markdown ? fmt::format("- **{}**: {}\n", mark, t.text)
                    : fmt::format("[{}] {}\n", mark, t.text);
  }
  return out;
}

}  // namespace bench
