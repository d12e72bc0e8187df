// linx-bench: the scenes of issue 4 in linx and, where they were found at configure time, in ODE,
// Bullet, MuJoCo and DART, one after another in one process, then MuJoCo's sample models run as
// they are in linx and MuJoCo (issue 16); prints one table, the model files' figures and the
// targets, or with --pareto the Pareto table of accuracy against time. See docs/performance.md.
#include "engine.hpp"
#include "model_files.hpp"
#include "report.hpp"
#include "runner.hpp"
#include "scenes.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace {

struct SceneEntry {
  std::string key;  // as named on the command line
  std::function<bench::Scene()> make;
  int bodies;  // for --max-bodies, without building it
};

std::vector<SceneEntry> sceneList(bool quick) {
  using namespace bench;
  std::vector<SceneEntry> list;
  const std::vector<int> chain_sizes =
      quick ? std::vector<int>{10} : std::vector<int>{10, 100, 1000};
  for (int n : chain_sizes) list.push_back({"chain", [n] { return hingeChain(n); }, n});
  for (int n : chain_sizes)
    list.push_back({"heavy-chain", [n] { return hingeChain(n, 1000.0); }, n});
  for (int base : quick ? std::vector<int>{10} : std::vector<int>{10, 20, 100}) {
    list.push_back({"pyramid", [base] { return pyramid(base); }, base * (base + 1) / 2});
  }
  for (int n : quick ? std::vector<int>{1000} : std::vector<int>{1000, 8000, 64000}) {
    list.push_back({"spheres", [n] { return pouredSpheres(n); }, n});
  }
  list.push_back({"slider-crank", [] { return sliderCrank(); }, 3});
  const int dolls = quick ? 4 : 100;
  list.push_back({"ragdolls", [dolls] { return ragdolls(dolls); }, 11 * dolls});
  return list;
}

/// The Pareto table's scenes (--pareto): the pyramids of 55 and 210 boxes and the 1,000-sphere
/// pile.
std::vector<SceneEntry> paretoSceneList(bool quick) {
  using namespace bench;
  std::vector<SceneEntry> list;
  for (int base : quick ? std::vector<int>{10} : std::vector<int>{10, 20}) {
    list.push_back({"pyramid", [base] { return pyramid(base); }, base * (base + 1) / 2});
  }
  list.push_back({"spheres", [] { return pouredSpheres(1000); }, 1000});
  return list;
}

/// The integrator table's mechanisms (--integrators), at the durations docs/integrators.md quotes.
std::vector<SceneEntry> integratorSceneList() {
  using namespace bench;
  return {{"a01-pendulum", [] { return pendulumA01(100.0); }, 1},
          {"a02-four-bar", [] { return fourBarA02(20.0); }, 81},
          {"heavy-top", [] { return heavyTop(5.0); }, 1},
          {"chain", [] { return swingingChain(10.0); }, 5},
          {"spatial-slider-crank", [] { return spatialSliderCrank(10.0); }, 3},
          {"a05-flyball-governor", [] { return flyballGovernorA05(10.0); }, 4}};
}

/// The model-file cases wanted, each run by every engine wanted (model_files.hpp); a case whose
/// file is missing becomes a line of `skipped`.
void runModelCases(const std::vector<bench::ModelCase>& cases,
                   const std::function<bool(const std::string&)>& wanted_engine, bool quick,
                   int max_bodies, double budget, std::vector<bench::Result>& results,
                   std::vector<bench::ModelFigures>& figures, std::vector<std::string>& skipped) {
  bench::ModelSchedule schedule;
  if (quick) {
    schedule.max_steps = 20;
    schedule.runs = 1;
  }
  std::vector<bench::ModelVariant> variants = bench::linxModelVariants();
  for (bench::ModelVariant& v : bench::mujocoModelVariants()) variants.push_back(std::move(v));
  for (const bench::ModelCase& model : cases) {
    if (max_bodies > 0 && model.bodies > max_bodies) continue;
    if (!std::filesystem::exists(model.path)) {
      skipped.push_back(fmt::format("{}: skipped: {} is missing (from the {})", model.key,
                                    model.path.string(), model.source));
      continue;
    }
    for (const bench::ModelVariant& v : variants) {
      if (!wanted_engine(v.engine)) continue;
      std::fprintf(stderr, "%s %s: %s ...", model.key.c_str(),
                   model.path.filename().string().c_str(), v.engine.c_str());
      std::fflush(stderr);
      const auto t0 = std::chrono::steady_clock::now();
      bench::ModelRun run = bench::runModel(model, v, schedule, budget);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, " %.1f s%s%s\n", s, run.result.note.empty() ? "" : ": ",
                   run.result.note.c_str());
      results.push_back(std::move(run.result));
      figures.push_back(std::move(run.figures));
    }
  }
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"linx-bench: linx against ODE, Bullet, MuJoCo and DART on the same scenes",
               "linx-bench"};
  std::vector<std::string> scene_names, engine_names;
  bool quick = false;
  int max_bodies = 0;
  double budget = 120.0;
  std::string markdown;
  bool pareto = false;
  std::vector<std::string> model_files;
  app.add_option(
         "--scene", scene_names,
         "Scenes to run (default all): chain, heavy-chain, pyramid, spheres, slider-crank, "
         "ragdolls, and the model files humanoid, 22_humanoids (MuJoCo's samples, from "
         "libmujoco-samples) and four_bar (examples/robots), each run as it is; with "
         "--integrators: a01-pendulum, a02-four-bar, heavy-top, chain, spatial-slider-crank, "
         "a05-flyball-governor")
      ->check(
          CLI::IsMember({"chain", "heavy-chain", "pyramid", "spheres", "slider-crank", "ragdolls",
                         "humanoid", "22_humanoids", "four_bar", "a01-pendulum", "a02-four-bar",
                         "heavy-top", "spatial-slider-crank", "a05-flyball-governor"}));
  app.add_option("--engine", engine_names,
                 "Engines to run (default every one built): linx, ode, bullet, mujoco, dart, "
                 "simbody (--integrators only)")
      ->check(CLI::IsMember({"linx", "ode", "bullet", "mujoco", "dart", "simbody"}));
  app.add_flag("--quick", quick,
               "Smallest size of each scene and 20 steps, one run of each model file (with "
               "--pareto: the 55-box pyramid and the sphere pile, the least and the most "
               "substeps and iterations): a smoke test, not a measurement");
  app.add_option("--max-bodies", max_bodies, "Skip scene sizes with more bodies than this")
      ->check(CLI::PositiveNumber);
  app.add_option("--budget", budget,
                 "Seconds of stepping per engine and scene before a run is cut short")
      ->check(CLI::PositiveNumber);
  app.add_option("--markdown", markdown,
                 "Also write the machine, command, table and targets to this Markdown file");
  app.add_option("--model", model_files,
                 "Also run this MJCF file as it is, in linx and MuJoCo, like the model files "
                 "among the scenes (with no --scene, only the files given)")
      ->check(CLI::ExistingFile);
  app.add_flag("--pareto", pareto,
               "Instead of the table and targets, the Pareto table: accuracy against time on the "
               "pyramids of 55 and 210 boxes and the 1,000-sphere pile, for linx's default step "
               "and its soft step at 1, 2, 4 and 8 substeps, and each peer at 10, 20, 50 and 100 "
               "iterations (and its default row when that is another solver)");
  bool integrators = false;
  app.add_flag("--integrators", integrators,
               "Instead of the table and targets, the integrator table: error against time on "
               "the mechanisms IFToMM A01 (pendulum, 100 s), A02 (N-four-bar, 20 s), the heavy "
               "top (5 s), a 5-link chain (10 s), a spatial slider-crank (10 s) and A05 (the stiff "
               "flyball governor, 10 s), for linx's "
               "step and its accurate integrator "
               "at tolerances 1e-6 to 1e-12, MuJoCo's Euler, implicit and RK4 integrators at h "
               "and smaller steps, Simbody's error-controlled integrators and ODE's dWorldStep")
      ->excludes("--pareto");
  CLI11_PARSE(app, argc, argv);

  std::string command = "linx-bench";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  const auto wanted = [](const std::vector<std::string>& list, const std::string& name) {
    return list.empty() || std::find(list.begin(), list.end(), name) != list.end();
  };

  // The Pareto table's counts: linx's soft-step substeps, the peers' iterations.
  const std::vector<int> substeps = quick ? std::vector<int>{1, 8} : std::vector<int>{1, 2, 4, 8};
  const std::vector<int> iterations =
      quick ? std::vector<int>{10, 100} : std::vector<int>{10, 20, 50, 100};
  const bool files_only = !model_files.empty() && scene_names.empty();  // --model alone
  std::vector<bench::Result> results;
  const std::vector<SceneEntry> scene_list = pareto        ? paretoSceneList(quick)
                                             : integrators ? integratorSceneList()
                                                           : sceneList(quick);
  for (const SceneEntry& entry : scene_list) {
    if (files_only || !wanted(scene_names, entry.key)) continue;
    if (max_bodies > 0 && entry.bodies > max_bodies) continue;
    bench::Scene scene = entry.make();
    if (quick) scene.steps = std::min(scene.steps, 20);
    std::vector<bench::Variant> variants;
    if (integrators) {
      variants = bench::linxIntegrators(scene);
      for (auto* more :
           {&bench::mujocoIntegrators, &bench::simbodyIntegrators, &bench::odeIntegrators}) {
        for (bench::Variant& v : more(scene)) variants.push_back(std::move(v));
      }
    } else if (pareto) {
      variants = bench::linxSweep(scene, substeps);
      for (auto* more :
           {&bench::odeSweep, &bench::bulletSweep, &bench::mujocoSweep, &bench::dartSweep}) {
        for (bench::Variant& v : more(scene, iterations)) variants.push_back(std::move(v));
      }
    } else {
      variants = bench::linxVariants(scene);
      for (auto* more : {&bench::odeVariants, &bench::bulletVariants, &bench::mujocoVariants,
                         &bench::dartVariants}) {
        for (bench::Variant& v : more(scene)) variants.push_back(std::move(v));
      }
    }
    for (const bench::Variant& v : variants) {
      if (!wanted(engine_names, lower(v.engine))) continue;
      std::fprintf(stderr, "%s %s: %s (%s) ...", scene.name.c_str(), scene.size.c_str(),
                   v.engine.c_str(), v.settings.c_str());
      std::fflush(stderr);
      const auto t0 = std::chrono::steady_clock::now();
      results.push_back(bench::run(scene, v, budget));
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, " %.1f s%s%s\n", s, results.back().note.empty() ? "" : ": ",
                   results.back().note.c_str());
    }
  }

  std::vector<bench::ModelFigures> figures;
  std::vector<std::string> skipped;
  if (!pareto && !integrators) {
    std::vector<bench::ModelCase> cases;
    for (const bench::ModelCase& c : bench::modelCases())
      if (!files_only && wanted(scene_names, c.key)) cases.push_back(c);
    for (const std::string& file : model_files) cases.push_back(bench::modelCase(file));
    runModelCases(
        cases, [&](const std::string& engine) { return wanted(engine_names, lower(engine)); },
        quick, max_bodies, budget, results, figures, skipped);
  }

  const std::vector<std::string> machine = bench::machineDescription();
  for (const std::string& line : machine) fmt::print("{}\n", line);
  std::string report = "Machine:\n\n";
  for (const std::string& line : machine) report += "- " + line + "\n";
  report += "\nCommand: `" + command + "`\n";
  if (pareto) {
    fmt::print("Command: {}\n{}", command, bench::paretoTable(results, false));
    report += bench::paretoTable(results, true);
  } else if (integrators) {
    const std::vector<bench::Target> targets = bench::integratorTargets(results);
    fmt::print("Command: {}\n{}\nTargets:\n{}", command, bench::integratorTable(results, false),
               bench::targetLines(targets, false));
    report += bench::integratorTable(results, true) + "\nTargets:\n\n" +
              bench::targetLines(targets, true);
  } else {
    const std::vector<bench::Target> targets = bench::targets(results);
    const std::string models = bench::modelLines(figures, skipped, false);
    fmt::print("Command: {}\n\n{}\n{}{}Targets:\n{}", command, bench::table(results, false), models,
               models.empty() ? "" : "\n", bench::targetLines(targets, false));
    const std::string models_md = bench::modelLines(figures, skipped, true);
    report += "\n" + bench::table(results, true) + (models_md.empty() ? "" : "\n" + models_md) +
              "\nTargets:\n\n" + bench::targetLines(targets, true);
  }
  bool failed = false;
  for (const bench::Result& r : results) failed = failed || (r.reference && !r.ran);

  if (!markdown.empty()) {
    // A file with the markers gets the report between them, the rest kept (docs/performance.md:
    // the table's between linx-bench:begin and :end, the Pareto table's between
    // linx-bench:pareto:begin and :end, the integrator table's between
    // linx-bench:integrators:begin and :end); a file with only another report's markers is
    // refused, any other file is the report alone. Written under a temporary name, then renamed.
    const std::string kind = pareto        ? "linx-bench:pareto:"
                             : integrators ? "linx-bench:integrators:"
                                           : "linx-bench:";
    const std::string begin = "<!-- " + kind + "begin -->", end = "<!-- " + kind + "end -->";
    std::string text = report;
    if (std::ifstream in{markdown}) {
      const std::string old{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      const auto b = old.find(begin), e = old.find(end);
      if (b != std::string::npos && e != std::string::npos && b < e) {
        text = old.substr(0, b + begin.size()) + "\n" + report + old.substr(e);
      } else if (old.find("<!-- linx-bench:") != std::string::npos) {
        std::fprintf(stderr, "linx-bench: %s has no %s ... %s markers for this report\n",
                     markdown.c_str(), begin.c_str(), end.c_str());
        return 2;
      }
    }
    const std::string tmp = markdown + ".tmp";
    bool ok = false;
    {
      std::ofstream out(tmp);
      out << text;
      ok = static_cast<bool>(out);
    }
    if (!ok || std::rename(tmp.c_str(), markdown.c_str()) != 0) {
      std::fprintf(stderr, "linx-bench: %s: cannot write\n", markdown.c_str());
      std::remove(tmp.c_str());
      return 2;
    }
  }
  // A linx run that failed is an error; a peer's failure is only a line in the table.
  return failed ? 1 : 0;
}
