// Model files run as they are (issue 16): the same MJCF file read by linx's importer and by
// MuJoCo's own, each engine stepping it for the same simulated time at the file's step with every
// control at zero. Timed like the scenes (the median time of a step, over several runs), in the
// same table; compared by physical figures instead of an accuracy figure: the moving mass each
// engine computed from the file and one body's centre of mass at the end.
#pragma once

#include "model_engine.hpp"
#include "runner.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace bench {

struct ModelCase {
  std::string key;             ///< its --scene name, the file's stem: "humanoid"
  std::filesystem::path path;  ///< the file
  /// The body whose centre of mass is compared: "torso"; empty: the file's first moving body.
  std::string body;
  int bodies = 0;      ///< its moving bodies, for --max-bodies without loading it
  std::string source;  ///< where the file comes from, for the note when it is missing
};

/// MuJoCo's own sample models from Debian's libmujoco-samples (humanoid.xml, 22_humanoids.xml)
/// and linx's four-bar example (examples/robots/four_bar.xml).
std::vector<ModelCase> modelCases();
/// A file named on the command line (--model): its stem as the key, its first moving body.
ModelCase modelCase(const std::filesystem::path& path);

/// How long and how often a case runs.
struct ModelSchedule {
  double duration = 2.0;  ///< simulated time of a run (s): round(duration / h) steps
  int max_steps = 0;      ///< at most this many steps a run (0: no limit)
  int runs = 3;           ///< each from the file loaded anew; the median is over all their steps
};

/// One engine's figures of physical agreement, at the end of its first run.
struct ModelFigures {
  std::string scene, file, engine, body;
  std::string refused;      ///< why the engine did not run the file; empty: it did
  int bodies = 0;           ///< moving bodies
  double mass = 0.0;        ///< their total mass (kg)
  double time = 0.0;        ///< simulated time at the end (s)
  Vec3 com = Vec3::Zero();  ///< the case's body's centre of mass then, world frame (m)
};

struct ModelRun {
  Result result;  ///< the table's row (no accuracy figure)
  ModelFigures figures;
};

/// Runs `variant` on the case's file: `schedule.runs` runs, each loading the file and stepping it,
/// every step timed, until `budget_s` seconds of stepping in all (the first run then stops where
/// it is, the others are left out; the row's note says which). A file the engine refuses is a
/// note ("cannot load: ..."), and its linx row is then no reference: not a failure of the run.
ModelRun runModel(const ModelCase& model, const ModelVariant& variant,
                  const ModelSchedule& schedule, double budget_s);

/// The engines' figures, file by file, each engine's against linx's where both ran, then the cases
/// skipped; one line each (Markdown: a list). Empty when there is nothing to say.
std::string modelLines(const std::vector<ModelFigures>& figures,
                       const std::vector<std::string>& skipped, bool markdown);

}  // namespace bench
