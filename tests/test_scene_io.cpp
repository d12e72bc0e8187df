// Scene files (docs/scene-format.md): valid scenes become the right definitions, every kind of
// mistake is reported with the path of the field and what is wrong, and the example scenes load
// and build.
#include <linx/import.hpp>
#include <linx/scene.hpp>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

using nlohmann::json;

// A small valid scene that the error cases edit.
json baseScene() {
  return json::parse(R"({
    "bodies": [
      {"name": "a", "mass": 2, "inertia": [1, 2, 3], "position": [1, 0, 0]},
      {"name": "b", "mass": 1, "shapes": [{"type": "sphere", "radius": 0.5}]}
    ],
    "joints": [
      {"name": "h", "type": "hinge", "body1": "a", "body2": "b", "anchor": [0, 0, 0],
       "axis": [0, 0, 2]}
    ]
  })");
}

linx::Scene parse(const json& scene) {
  return linx::parseScene(scene.dump(), "scene.json");
}

// The error parsing `text` raises (and a test failure when there is none).
linx::SceneError errorOf(const std::string& text) {
  try {
    linx::parseScene(text, "scene.json");
  } catch (const linx::SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for: " << text;
  return linx::SceneError("", "", "");
}

struct Case {
  std::function<void(json&)> edit;  // applied to baseScene()
  std::string field;
  std::string problem;  // a substring of the message
};

void expectErrors(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    json scene = baseScene();
    c.edit(scene);
    SCOPED_TRACE(scene.dump());
    const linx::SceneError e = errorOf(scene.dump());
    EXPECT_EQ(e.file(), "scene.json");
    EXPECT_EQ(e.field(), c.field);
    EXPECT_NE(e.problem().find(c.problem), std::string::npos) << "problem: " << e.problem();
  }
}

// ---------------------------------------------------------------------------------------------
// Valid scenes

TEST(SceneRead, DefaultsOfAMinimalScene) {
  const linx::Scene s =
      parse(json::parse(R"({"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]}]})"));
  const linx::WorldSettings defaults;
  EXPECT_EQ(s.file, "scene.json");
  EXPECT_EQ(s.settings.gravity, linx::Vec3(0, 0, -9.81));
  EXPECT_EQ(s.settings.timestep, 0.001);
  EXPECT_EQ(s.duration, 1.0);
  EXPECT_EQ(s.settings.solver.type, defaults.solver.type);
  EXPECT_EQ(s.settings.solver.iterations, defaults.solver.iterations);
  ASSERT_EQ(s.bodies.size(), 1u);
  const linx::BodyDef& b = s.bodies[0];
  EXPECT_EQ(b.position, linx::Vec3::Zero());
  EXPECT_TRUE(b.orientation.coeffs().isApprox(linx::Quat::Identity().coeffs()));
  EXPECT_EQ(b.linear_velocity, linx::Vec3::Zero());
  EXPECT_EQ(b.angular_velocity, linx::Vec3::Zero());
  EXPECT_FALSE(b.is_static);
  EXPECT_TRUE(s.joints.empty());
}

TEST(SceneRead, EveryField) {
  const linx::Scene s = parse(json::parse(R"({
    "gravity": [0, -9.8, 0], "timestep": 0.002, "duration": 3.5,
    "solver": {"type": "pgs", "iterations": 40, "tolerance": 1e-8, "erp": 0.3, "cfm": 1e-6,
               "warm_start": false, "sor": 1.3, "substeps": 4, "post_stabilization": 6,
               "projection": true, "projection_iterations": 5, "projection_tolerance": 1e-9,
               "geometric_stiffness": false},
    "contact": {"max_push_out": 1.5},
    "faults": {"energy": false, "kinetic_fraction": 0.25, "height": 0.5, "speed": 2},
    "bodies": [
      {"name": "ground", "static": true},
      {"name": "arm", "mass": 2, "inertia": [[2, 0.1, 0], [0.1, 3, 0], [0, 0, 4]],
       "position": [1, 2, 3], "orientation": [0, 0, 0, 2], "linear_velocity": [1, 0, 0],
       "angular_velocity": [0, 0, 1],
       "shapes": [{"type": "box", "size": [1, 2, 3], "position": [0, 0, 1],
                   "orientation": [1, 0, 0, 0]}]}
    ],
    "joints": [
      {"name": "s", "type": "slider", "body1": "arm", "body2": "ground", "axis": [3, 0, 4],
       "limits": {"lower": -0.5}, "motor": {"max_force": 10}, "erp": 0.5, "cfm": 0.01},
      {"name": "f", "type": "fixed", "body1": "arm", "anchor": [7, 8, 9]},
      {"name": "p", "type": "ball", "body1": "arm", "anchor": [1, 1, 1]},
      {"name": "h", "type": "hinge", "body1": "arm", "body2": "world", "anchor": [0, 0, 0],
       "axis": [0, 1, 0], "limits": {"lower": -1, "upper": 1},
       "motor": {"target_velocity": -2, "max_force": 5}}
    ]
  })"));
  EXPECT_EQ(s.settings.gravity, linx::Vec3(0, -9.8, 0));
  EXPECT_EQ(s.settings.timestep, 0.002);
  EXPECT_EQ(s.duration, 3.5);
  const linx::SolverSettings& solver = s.settings.solver;
  EXPECT_EQ(solver.type, linx::SolverType::Pgs);
  EXPECT_EQ(solver.iterations, 40);
  EXPECT_EQ(solver.tolerance, 1e-8);
  EXPECT_EQ(solver.erp, 0.3);
  EXPECT_EQ(solver.cfm, 1e-6);
  EXPECT_FALSE(solver.warm_start);
  EXPECT_EQ(solver.sor, 1.3);
  EXPECT_EQ(solver.substeps, 4);
  EXPECT_EQ(solver.post_stabilization, 6);
  EXPECT_TRUE(solver.projection);
  EXPECT_EQ(solver.projection_iterations, 5);
  EXPECT_EQ(solver.projection_tolerance, 1e-9);
  EXPECT_FALSE(solver.geometric_stiffness);
  EXPECT_EQ(s.settings.contact.max_push_out, 1.5);
  const linx::FaultSettings& faults = s.settings.faults;
  EXPECT_FALSE(faults.energy);
  EXPECT_EQ(faults.kinetic_fraction, 0.25);
  EXPECT_EQ(faults.height, 0.5);
  EXPECT_EQ(faults.speed, 2.0);

  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_TRUE(s.bodies[0].is_static);
  const linx::BodyDef& arm = s.bodies[1];
  EXPECT_EQ(arm.name, "arm");
  EXPECT_EQ(arm.mass, 2.0);
  linx::Mat3 inertia;
  inertia << 2, 0.1, 0, 0.1, 3, 0, 0, 0, 4;
  EXPECT_EQ(arm.inertia, inertia);  // given: not computed from the shape
  EXPECT_EQ(arm.position, linx::Vec3(1, 2, 3));
  EXPECT_EQ(arm.orientation.coeffs(), linx::Quat(0, 0, 0, 1).coeffs());  // normalized
  EXPECT_EQ(arm.linear_velocity, linx::Vec3(1, 0, 0));
  EXPECT_EQ(arm.angular_velocity, linx::Vec3(0, 0, 1));
  ASSERT_EQ(arm.shapes.size(), 1u);
  EXPECT_EQ(arm.shapes[0].type, linx::ShapeType::Box);
  EXPECT_EQ(arm.shapes[0].size, linx::Vec3(1, 2, 3));
  EXPECT_EQ(arm.shapes[0].position, linx::Vec3(0, 0, 1));

  ASSERT_EQ(s.joints.size(), 4u);
  const linx::SceneJoint& slider = s.joints[0];
  EXPECT_EQ(slider.type, "slider");
  EXPECT_EQ(slider.def.name, "s");
  EXPECT_EQ(slider.def.body1, linx::BodyId{1});
  EXPECT_EQ(slider.def.body2, linx::BodyId{0});
  EXPECT_EQ(slider.def.anchor, arm.position);  // defaults to body1's position
  EXPECT_TRUE(slider.def.axis.isApprox(linx::Vec3(0.6, 0, 0.8), 1e-15));
  ASSERT_TRUE(slider.def.coordinates[0].limits);
  EXPECT_EQ(slider.def.coordinates[0].limits->lower, -0.5);
  EXPECT_EQ(slider.def.coordinates[0].limits->upper, linx::kInfinity);
  ASSERT_TRUE(slider.def.coordinates[0].motor);
  EXPECT_EQ(slider.def.coordinates[0].motor->target_velocity, 0.0);
  EXPECT_EQ(slider.def.coordinates[0].motor->max_force, 10.0);
  EXPECT_EQ(slider.def.erp, 0.5);
  EXPECT_EQ(slider.def.cfm, 0.01);

  const linx::SceneJoint& fixed = s.joints[1];
  EXPECT_EQ(fixed.def.body2, linx::kWorldBody);  // body2 left out
  EXPECT_EQ(fixed.def.anchor, linx::Vec3(7, 8, 9));
  EXPECT_FALSE(fixed.def.coordinates[0].limits);
  EXPECT_FALSE(fixed.def.erp);

  EXPECT_EQ(s.joints[2].type, "ball");
  const linx::SceneJoint& hinge = s.joints[3];
  EXPECT_EQ(hinge.def.body2, linx::kWorldBody);  // "world"
  EXPECT_EQ(hinge.def.axis, linx::Vec3(0, 1, 0));
  EXPECT_EQ(hinge.def.coordinates[0].limits->lower, -1.0);
  EXPECT_EQ(hinge.def.coordinates[0].limits->upper, 1.0);
  EXPECT_EQ(hinge.def.coordinates[0].motor->target_velocity, -2.0);
}

TEST(SceneRead, StaticBodyNeedsNoMassOrInertia) {
  const linx::Scene s = parse(json::parse(R"({"bodies": [{"name": "ground", "static": true}]})"));
  EXPECT_TRUE(s.bodies[0].is_static);
}

// Inertia of a solid of revolution about z with radius profile R(z), integrated by Simpson's rule
// piece by piece. R^2 is a polynomial of degree <= 2 on each piece, so the integrands are
// polynomials of degree <= 4: the rule's error, (h^4/180) times the fourth derivative, is below
// 1e-15 here.
struct Revolution {
  double mass = 0, izz = 0, ixx = 0;  // for unit density
};
Revolution integrate(const std::function<double(double)>& radius2,
                     const std::vector<double>& breaks) {
  Revolution out;
  const double pi = std::acos(-1.0);
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    const int n = 1024;
    const double a = breaks[k], h = (breaks[k + 1] - a) / n;
    for (int i = 0; i <= n; ++i) {
      const double z = a + i * h;
      const double w = (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0) * h / 3.0;
      const double r2 = std::max(radius2(z), 0.0);
      out.mass += w * pi * r2;
      out.izz += w * 0.5 * pi * r2 * r2;            // discs: m r^2 / 2
      out.ixx += w * pi * r2 * (r2 / 4.0 + z * z);  // discs: m r^2 / 4 + m z^2
    }
  }
  return out;
}

linx::Mat3 inertiaOf(const std::string& shape, double mass) {
  json scene = json::parse(R"({"bodies": [{"name": "a"}]})");
  scene["bodies"][0]["mass"] = mass;
  scene["bodies"][0]["shapes"] = json::array({json::parse(shape)});
  return *parse(scene).bodies[0].inertia;
}

TEST(SceneRead, InertiaFromShapes) {
  const double m = 3.0;
  EXPECT_TRUE(inertiaOf(R"({"type": "sphere", "radius": 0.5})", m)
                  .isApprox(linx::Mat3::Identity() * 0.4 * m * 0.25, 1e-15));
  EXPECT_TRUE(inertiaOf(R"({"type": "box", "size": [1, 2, 3]})", m)
                  .isApprox(linx::Mat3(linx::Vec3(13, 10, 5).asDiagonal()) * (m / 12), 1e-15));

  const double r = 0.2, L = 0.6;
  const std::string dims = R"(, "radius": 0.2, "length": 0.6})";
  const Revolution cylinder = integrate([&](double) { return r * r; }, {-L / 2, L / 2});
  const Revolution capsule = integrate(
      [&](double z) {
        const double beyond = std::max(std::abs(z) - L / 2, 0.0);  // into a cap
        return r * r - beyond * beyond;
      },
      {-L / 2 - r, -L / 2, L / 2, L / 2 + r});
  for (const auto& [type, exact] :
       {std::pair{"cylinder", cylinder}, std::pair{"capsule", capsule}}) {
    SCOPED_TRACE(type);
    const linx::Mat3 I = inertiaOf(std::string(R"({"type": ")") + type + '"' + dims, m);
    const double scale = m / exact.mass;
    EXPECT_NEAR(I(0, 0), exact.ixx * scale, 1e-12);
    EXPECT_NEAR(I(1, 1), exact.ixx * scale, 1e-12);
    EXPECT_NEAR(I(2, 2), exact.izz * scale, 1e-12);
    EXPECT_TRUE(I.isDiagonal(1e-15));
  }
  // A capsule of length 0 is a sphere.
  EXPECT_TRUE(inertiaOf(R"({"type": "capsule", "radius": 0.5, "length": 0})", m)
                  .isApprox(inertiaOf(R"({"type": "sphere", "radius": 0.5})", m), 1e-15));
}

TEST(SceneRead, InertiaOfARotatedAndOffsetShape) {
  // A box turned a quarter turn about z swaps its x and y moments; an offset d along z adds
  // m d^2 about x and y (parallel axes).
  const double m = 2.0, s = std::sqrt(0.5);
  json shape = {{"type", "box"}, {"size", {1, 2, 3}}, {"orientation", {s, 0, 0, s}}};
  linx::Mat3 expected = linx::Mat3(linx::Vec3(10, 13, 5).asDiagonal()) * (m / 12);
  EXPECT_TRUE(inertiaOf(shape.dump(), m).isApprox(expected, 1e-14));
  shape["position"] = {0, 0, 0.5};
  expected += linx::Mat3(linx::Vec3(1, 1, 0).asDiagonal()) * (m * 0.25);
  EXPECT_TRUE(inertiaOf(shape.dump(), m).isApprox(expected, 1e-14));
}

TEST(SceneRead, ExamplesLoadAndBuild) {
  const std::filesystem::path dir = LINX_EXAMPLES_DIR;
  const std::vector<std::pair<std::string, std::pair<int, int>>> examples = {
      {"pendulum.json", {1, 1}},      {"double_pendulum.json", {2, 2}},
      {"hinge_chain.json", {10, 10}}, {"slider_incline.json", {1, 1}},
      {"slider_crank.json", {3, 4}},  {"wrecking_ball.json", {10, 9}},
  };
  for (const auto& [file, counts] : examples) {
    SCOPED_TRACE(file);
    const linx::Scene scene = linx::loadScene(dir / file);
    const linx::World world = linx::buildWorld(scene);
    EXPECT_EQ(world.bodyCount(), counts.first);
    EXPECT_EQ(world.jointCount(), counts.second);
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      EXPECT_EQ(world.findBody(scene.bodies[i].name), linx::BodyId{static_cast<int>(i)});
    }
    for (const linx::SceneJoint& j : scene.joints) EXPECT_TRUE(world.findJoint(j.def.name));
  }
}

TEST(SceneRead, ExampleGeometry) {
  const std::filesystem::path dir = LINX_EXAMPLES_DIR;
  const linx::Scene crank = linx::loadScene(dir / "slider_crank.json");
  EXPECT_EQ(crank.settings.solver.type, linx::SolverType::Exact);
  EXPECT_EQ(crank.joints[0].def.coordinates[0].motor->target_velocity, 2 * std::acos(-1.0));
  EXPECT_EQ(crank.joints[3].type, "slider");
  EXPECT_EQ(crank.joints[3].def.anchor, linx::Vec3(0.4, 0, 0));  // the piston's centre

  const linx::Scene incline = linx::loadScene(dir / "slider_incline.json");
  const double down = std::acos(-1.0) / 6;  // 30 degrees
  EXPECT_TRUE(
      incline.joints[0].def.axis.isApprox(linx::Vec3(std::cos(down), 0, -std::sin(down)), 1e-15));
}

// ---------------------------------------------------------------------------------------------
// Building

TEST(SceneBuild, EngineRefusalsNameTheDefinition) {
  linx::Scene scene = parse(baseScene());
  scene.bodies[1].mass = -1;  // past the reader: the engine refuses it
  linx::SceneError e("", "", "");
  try {
    linx::buildWorld(scene);
    FAIL() << "no error";
  } catch (const linx::SceneError& error) {
    e = error;
  }
  // The engine's message names the field: it joins the definition's path.
  EXPECT_EQ(e.field(), "bodies[1].mass");
  EXPECT_EQ(e.problem(), "must be finite and > 0");

  scene = parse(baseScene());
  scene.joints[0].def.body2 = linx::BodyId{7};
  try {
    linx::buildWorld(scene);
    FAIL() << "no error";
  } catch (const linx::SceneError& error) {
    EXPECT_EQ(error.field(), "joints[0].body2");
    EXPECT_EQ(error.file(), "scene.json");
  }
}

TEST(SceneBuild, BodiesKeepFileOrderAndState) {
  const linx::Scene scene = parse(baseScene());
  const linx::World world = linx::buildWorld(scene);
  EXPECT_EQ(world.body(linx::BodyId{0}).name(), "a");
  EXPECT_EQ(world.body(linx::BodyId{0}).position(), linx::Vec3(1, 0, 0));
  EXPECT_EQ(world.body(linx::BodyId{1}).mass(), 1.0);
  EXPECT_EQ(world.joint(linx::JointId{0}).type(), "hinge");
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST(SceneError, MessageIsFileFieldProblem) {
  EXPECT_STREQ(linx::SceneError("s.json", "bodies[0].mass", "must be > 0, got 0").what(),
               "s.json: bodies[0].mass: must be > 0, got 0");
  EXPECT_STREQ(linx::SceneError("s.json", "", "cannot open").what(), "s.json: cannot open");
}

TEST(SceneError, Files) {
  const auto missing = std::filesystem::path(LINX_EXAMPLES_DIR) / "no_such_scene.json";
  try {
    linx::loadScene(missing);
    FAIL() << "no error";
  } catch (const linx::SceneError& e) {
    EXPECT_EQ(e.file(), missing.string());
    EXPECT_EQ(e.field(), "");
    EXPECT_NE(e.problem().find("cannot open"), std::string::npos) << e.problem();
  }
  try {
    linx::loadScene(LINX_EXAMPLES_DIR);
    FAIL() << "no error";
  } catch (const linx::SceneError& e) {
    EXPECT_EQ(e.problem(), "is a directory");
  }
}

// Hostile files (issue 17): a device, a pipe, a file far larger than any scene, files outside the
// scene's folder. Each is refused, naming the file or the field, before a byte is read from it.
TEST(SceneError, DevicesPipesHugeFilesAndOutsidePathsAreRefused) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("linx_inputs_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "scene");
  fs::create_directories(root / "elsewhere");
  const auto problem = [](const fs::path& scene, linx::ImportOptions options = {}) -> std::string {
    try {
      linx::loadScene(scene, options);
    } catch (const linx::SceneError& e) {
      return e.field() + ": " + e.problem();
    }
    return "accepted";
  };
  // The scene itself: /dev/zero (endless), a FIFO (no writer: opening must not wait), a sparse
  // file of 300 MiB.
  EXPECT_EQ(problem("/dev/zero"), ": not a regular file (a device, a pipe or a socket)");
  ASSERT_EQ(::mkfifo((root / "scene" / "pipe.json").c_str(), 0600), 0);
  EXPECT_EQ(problem(root / "scene" / "pipe.json"),
            ": not a regular file (a device, a pipe or a socket)");
  {
    std::ofstream(root / "scene" / "huge.json") << "{}";
    fs::resize_file(root / "scene" / "huge.json", 300 * 1024 * 1024);
  }
  EXPECT_EQ(problem(root / "scene" / "huge.json"),
            ": is 300 MiB, above the limit of 256 MiB for a scene");

  // Meshes: a link to /dev/zero, a sparse 600 MiB file, one outside the folder, allowed by option.
  const auto sceneWithMesh = [&](const std::string& file) {
    const fs::path scene = root / "scene" / "mesh.json";
    std::ofstream(scene) << R"({"bodies": [{"name": "ground", "static": true, "shapes": [)"
                         << R"({"type": "mesh", "file": ")" << file << R"("}]}]})";
    return scene;
  };
  // A link to /dev/zero leads out of the folder; allowed out, it is still no regular file.
  linx::ImportOptions allow;
  allow.allow_outside_paths = true;
  fs::create_symlink("/dev/zero", root / "scene" / "zero.obj");
  EXPECT_NE(problem(sceneWithMesh("zero.obj")).find("is outside the scene's folder"),
            std::string::npos);
  EXPECT_EQ(problem(sceneWithMesh("zero.obj"), allow),
            "bodies[0].shapes[0].file: mesh file " + (root / "scene" / "zero.obj").string() +
                ": not a regular file (a device, a pipe or a socket)");
  {
    std::ofstream(root / "scene" / "big.obj") << "v 0 0 0\n";
    fs::resize_file(root / "scene" / "big.obj", 600 * 1024 * 1024);
  }
  EXPECT_NE(problem(sceneWithMesh("big.obj"))
                .find("big.obj: is 600 MiB, above the limit of 512 MiB for a mesh"),
            std::string::npos);
  std::ofstream(root / "elsewhere" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string outside = problem(sceneWithMesh("../elsewhere/tri.obj"));
  EXPECT_EQ(outside.rfind("bodies[0].shapes[0].file: '", 0), 0u) << outside;
  EXPECT_NE(
      outside.find("' is outside the scene's folder " + fs::canonical(root / "scene").string() +
                   " (linx reads only files there; --allow-outside-paths lifts this)"),
      std::string::npos)
      << outside;
  // A link inside the folder that leads out is outside too; the option lets both be read.
  fs::create_symlink(root / "elsewhere" / "tri.obj", root / "scene" / "link.obj");
  EXPECT_NE(problem(sceneWithMesh("link.obj")).find("is outside the scene's folder"),
            std::string::npos);
  EXPECT_EQ(problem(sceneWithMesh("../elsewhere/tri.obj"), allow), "accepted");
  EXPECT_EQ(problem(sceneWithMesh("link.obj"), allow), "accepted");
  std::ofstream(root / "scene" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(problem(sceneWithMesh("tri.obj")), "accepted");
  fs::remove_all(root);
}

// A thousand identical hinges took 100 s a step (a dense solve of redundant rows): loadModel names
// such repeats with a warning, one per group; joints that differ in anchor, axis, type or bodies
// are not repeats.
TEST(SceneRead, RepeatedJointsAreNamedWithAWarning) {
  namespace fs = std::filesystem;
  const fs::path file =
      fs::temp_directory_path() / ("linx_repeats_" + std::to_string(::getpid()) + ".json");
  json scene = {{"bodies", json::array()}, {"joints", json::array()}};
  for (const char* name : {"a", "b"})
    scene["bodies"].push_back({{"name", name}, {"mass", 1}, {"inertia", {1, 1, 1}}});
  const auto hinge = [](const std::string& name, std::vector<double> anchor,
                        std::vector<double> axis, const char* b1 = "a", const char* b2 = "b") {
    return json{{"name", name}, {"type", "hinge"},  {"body1", b1},
                {"body2", b2},  {"anchor", anchor}, {"axis", axis}};
  };
  for (const char* name : {"h0", "h1", "h2", "h3", "h4"})
    scene["joints"].push_back(hinge(name, {0, 0, 0}, {0, 0, 1}));
  scene["joints"].push_back(hinge("flipped", {0, 0, 0}, {0, 0, -1}, "b", "a"));  // the same hinge
  scene["joints"].push_back(hinge("other_axis", {0, 0, 0}, {0, 1, 0}));
  scene["joints"].push_back(hinge("other_anchor", {0, 0, 1e-3}, {0, 0, 1}));
  scene["joints"].push_back(hinge("to_world", {0, 0, 0}, {0, 0, 1}, "a", "world"));
  // Mimics tie joints, not bodies: ties of different joints are not repeats (bullet3's NAO, with
  // its mimicking fingers, was warned of "the same mimic between bodies world and world"); the
  // same tie twice is.
  const auto mimic = [](const std::string& name, const char* leader, const char* follower) {
    return json{{"name", name}, {"type", "mimic"}, {"leader", leader}, {"follower", follower}};
  };
  scene["joints"].push_back(mimic("m1", "other_axis", "other_anchor"));
  scene["joints"].push_back(mimic("m2", "other_axis", "to_world"));
  scene["joints"].push_back(mimic("m3", "other_anchor", "to_world"));
  scene["joints"].push_back(mimic("m1_again", "other_axis", "other_anchor"));
  std::ofstream(file) << scene.dump();
  const linx::Scene loaded = linx::loadModel(file);
  fs::remove(file);
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_EQ(loaded.warnings[1],
            file.string() +
                ": joints[9] (m1) repeated by 1 more (joints[12] (m1_again)): the same mimic "
                "tying joints 'other_axis' and 'other_anchor' at the same anchor and axis; their "
                "rows are redundant, which the exact solver solves densely at a cost growing with "
                "the cube of their number; keep one");
  std::string expected = file.string();
  expected +=
      ": joints[0] (h0) repeated by 5 more (joints[1] (h1), joints[2] (h2), joints[3] "
      "(h3), ...): the same hinge between bodies 'a' and 'b' at the same anchor and "
      "axis; their rows are redundant, which the exact solver solves densely at a cost "
      "growing with the cube of their number; keep one";
  EXPECT_EQ(loaded.warnings[0], expected);
}

// A joint or a spring between two things that never move (static bodies, the world) never acts:
// named with a warning. One with a moving or kinematic body is not.
TEST(SceneRead, JointsThatNeverActAreNamedWithAWarning) {
  namespace fs = std::filesystem;
  const fs::path file =
      fs::temp_directory_path() / ("linx_idle_" + std::to_string(::getpid()) + ".json");
  const json scene = json::parse(R"({
    "bodies": [{"name": "post", "static": true},
               {"name": "slab", "static": true},
               {"name": "cart", "kinematic": true, "linear_velocity": [1, 0, 0]},
               {"name": "bob", "mass": 1, "inertia": [1, 1, 1]}],
    "joints": [{"name": "weld", "type": "fixed", "body1": "post", "body2": "slab"},
               {"name": "pin", "type": "hinge", "body1": "post", "anchor": [0, 0, 0],
                "axis": [0, 0, 1]},
               {"name": "tow", "type": "fixed", "body1": "cart"},
               {"name": "swing", "type": "hinge", "body1": "bob", "anchor": [0, 0, 0],
                "axis": [0, 0, 1]}],
    "springs": [{"name": "idle", "body1": "post", "anchor1": [0, 0, 0], "anchor2": [1, 0, 0],
                 "stiffness": 10}]})");
  std::ofstream(file) << scene.dump();
  const linx::Scene loaded = linx::loadModel(file);
  fs::remove(file);
  const std::string tail = ", neither of which moves (static bodies, the world): it never acts";
  ASSERT_EQ(loaded.warnings.size(), 3u);
  EXPECT_EQ(loaded.warnings[0],
            file.string() + ": joints[0] (weld): joins 'post' and 'slab'" + tail);
  EXPECT_EQ(loaded.warnings[1],
            file.string() + ": joints[1] (pin): joins 'post' and the world" + tail);
  EXPECT_EQ(loaded.warnings[2],
            file.string() + ": springs[0] (idle): joins 'post' and the world" + tail);
}

TEST(SceneError, MalformedJson) {
  linx::SceneError e = errorOf("{\n  \"timestep\": 0.001\n  \"duration\": 1\n}");
  EXPECT_EQ(e.field(), "line 3, column 12");  // where the parser gave up: after "duration"
  EXPECT_NE(e.problem().find("syntax error"), std::string::npos) << e.problem();
  EXPECT_EQ(errorOf("").problem(), "the file is empty (a scene is a JSON object, {...})");
  EXPECT_EQ(errorOf(std::string("{\0}", 3)).problem(),
            "a NUL byte at offset 1: a binary file, not JSON text");
  // A byte that is not printable text is quoted escaped.
  EXPECT_NE(errorOf("{\"a\xff\": 1}").problem().find("last read: '\"a\\xff'"), std::string::npos)
      << errorOf("{\"a\xff\": 1}").problem();
  EXPECT_EQ(errorOf("{} x").field(), "line 1, column 4");
  EXPECT_EQ(errorOf(R"({"bodies": [1,]})").field(), "line 1, column 15");
  // JSON has no comments.
  EXPECT_EQ(errorOf("// scene\n{}").field(), "line 1, column 1");
}

TEST(SceneError, NumbersTooLargeForADouble) {
  std::string text = baseScene().dump();
  const auto replace = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return errorOf(t);
  };
  linx::SceneError e = replace(R"("mass":2)", R"("mass":1e999)");
  EXPECT_EQ(e.field(), "bodies[0].mass");
  EXPECT_NE(e.problem().find("1e999"), std::string::npos) << e.problem();
  EXPECT_EQ(replace(R"("anchor":[0,0,0])", R"("anchor":[0,-1e400,0])").field(),
            "joints[0].anchor[1]");
  EXPECT_EQ(replace(R"({"bodies")", R"({"gravity":[0,0,1e999],"bodies")").field(), "gravity[2]");
}

TEST(SceneError, DuplicateKeys) {
  linx::SceneError e = errorOf(R"({"timestep": 0.1, "timestep": 0.2, "bodies": []})");
  EXPECT_EQ(e.field(), "timestep");
  EXPECT_EQ(e.problem(), "duplicate key");
  e = errorOf(R"({"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]},
                             {"name": "b", "mass": 1, "mass": 2}]})");
  EXPECT_EQ(e.field(), "bodies[1].mass");
  e = errorOf(R"({"bodies": [{"name": "a", "shapes": [[], {"radius": 1, "radius": 2}]}]})");
  EXPECT_EQ(e.field(), "bodies[0].shapes[1].radius");
}

TEST(SceneError, TopLevel) {
  EXPECT_EQ(errorOf("[1, 2]").problem(), "a scene must be a JSON object, got an array");
  expectErrors({
      {[](json& s) {
         s["gravty"] = {0, 0, -1};
       },
       "gravty", "unknown field (did you mean 'gravity'?)"},
      {[](json& s) { s["comment"] = "x"; }, "comment", "unknown field"},
      {[](json& s) {
         s["gravity"] = {0, 0};
       },
       "gravity", "expected an array of 3 numbers, got 2 items"},
      {[](json& s) { s["gravity"] = "down"; }, "gravity",
       "expected an array of 3 numbers, got a string"},
      {[](json& s) {
         s["gravity"] = {0, "a", 0};
       },
       "gravity[1]", "expected a number, got a string"},
      {[](json& s) { s["timestep"] = 0; }, "timestep", "must be > 0, got 0"},
      {[](json& s) { s["timestep"] = -0.001; }, "timestep", "must be > 0, got -0.001"},
      {[](json& s) { s["duration"] = "5"; }, "duration", "expected a number, got a string"},
      {[](json& s) { s["duration"] = true; }, "duration", "expected a number, got a boolean"},
      {[](json& s) { s["threads"] = -1; }, "threads", "must be an integer >= 0, got -1"},
      {[](json& s) { s["threads"] = 1.5; }, "threads", "must be an integer >= 0, got 1.5"},
      {[](json& s) { s["threads"] = 5000; }, "threads", "must be at most 1024, got 5000"},
      {[](json& s) { s.erase("bodies"); }, "bodies", "missing required field"},
      {[](json& s) { s["bodies"] = json::array(); }, "bodies", "must contain at least one body"},
      {[](json& s) { s["bodies"] = json::object(); }, "bodies", "expected an array, got an object"},
      {[](json& s) { s["joints"] = nullptr; }, "joints", "expected an array, got null"},
  });
}

TEST(SceneError, Faults) {
  expectErrors({
      {[](json& s) { s["faults"] = true; }, "faults", "expected an object, got a boolean"},
      {[](json& s) { s["faults"]["energy"] = 1; }, "faults.energy",
       "expected true or false, got a number"},
      {[](json& s) { s["faults"]["kinetic_fraction"] = -0.5; }, "faults.kinetic_fraction",
       "must be >= 0, got -0.5"},
      {[](json& s) { s["faults"]["speeds"] = 1; }, "faults.speeds",
       "unknown field (did you mean 'speed'?)"},
      {[](json& s) { s["contact"]["max_push_out"] = -1; }, "contact.max_push_out",
       "must be >= 0, got -1"},
  });
}

TEST(SceneError, Integrator) {
  expectErrors({
      {[](json& s) { s["integrator"] = "rk4"; }, "integrator",
       "unknown value 'rk4' (expected \"step\", \"accurate\" or \"auto\")"},
      {[](json& s) { s["integrator"] = 1; }, "integrator",
       "expected \"auto\", \"step\", \"accurate\" or an object, got a number"},
      {[](json& s) {
         s["integrator"] = {{"type", "Accurate"}};
       },
       "integrator.type", "unknown value 'Accurate' (expected \"step\", \"accurate\" or \"auto\")"},
      {[](json& s) {
         s["integrator"] = {{"tolerence", 1e-9}};
       },
       "integrator.tolerence", "unknown field (did you mean 'tolerance'?)"},
      {[](json& s) {
         s["integrator"] = {{"tolerance", 0}};
       },
       "integrator.tolerance", "must be between 1e-14 and 0.01, got 0"},
      {[](json& s) {
         s["integrator"] = {{"tolerance", 0.5}};
       },
       "integrator.tolerance", "must be between 1e-14 and 0.01, got 0.5"},
  });
}

TEST(SceneIo, IntegratorReadsAsAStringOrAnObject) {
  const auto read = [](const std::string& integrator) {
    return linx::parseScene(R"({"integrator": )" + integrator +
                                R"(, "bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 1]}]})",
                            "t.json")
        .settings.integrator;
  };
  EXPECT_EQ(read(R"("step")").type, linx::IntegratorType::Step);
  EXPECT_EQ(read(R"("accurate")").type, linx::IntegratorType::Accurate);
  EXPECT_EQ(read(R"("auto")").type, linx::IntegratorType::Auto);
  EXPECT_EQ(read(R"("accurate")").tolerance, linx::IntegratorSettings{}.tolerance);
  const linx::IntegratorSettings s = read(R"({"type": "accurate", "tolerance": 1e-8})");
  EXPECT_EQ(s.type, linx::IntegratorType::Accurate);
  EXPECT_EQ(s.tolerance, 1e-8);
  // The type defaults to "auto", in an object or without the field.
  EXPECT_EQ(read(R"({"tolerance": 1e-8})").type, linx::IntegratorType::Auto);
  EXPECT_EQ(
      linx::parseScene(R"({"bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 1]}]})", "t.json")
          .settings.integrator.type,
      linx::IntegratorType::Auto);
}

TEST(SceneError, Solver) {
  expectErrors({
      {[](json& s) { s["solver"] = "pgs"; }, "solver", "expected an object, got a string"},
      {[](json& s) { s["solver"]["type"] = "fast"; }, "solver.type",
       "unknown value 'fast' (expected \"auto\", \"exact\", \"pgs\" or \"soft\")"},
      {[](json& s) { s["solver"]["iteration"] = 5; }, "solver.iteration",
       "unknown field (did you mean 'iterations'?)"},
      {[](json& s) { s["solver"]["iterations"] = 0; }, "solver.iterations",
       "must be an integer >= 1, got 0"},
      {[](json& s) { s["solver"]["iterations"] = 2.5; }, "solver.iterations",
       "must be an integer >= 1, got 2.5"},
      {[](json& s) { s["solver"]["iterations"] = 1e12; }, "solver.iterations",
       "must be an integer from 1 to 2147483647, got 1e+12"},
      {[](json& s) { s["solver"]["tolerance"] = -1; }, "solver.tolerance", "must be >= 0, got -1"},
      {[](json& s) { s["solver"]["erp"] = 1.5; }, "solver.erp", "must be between 0 and 1, got 1.5"},
      {[](json& s) { s["solver"]["cfm"] = -1e-9; }, "solver.cfm", "must be >= 0"},
      {[](json& s) { s["solver"]["warm_start"] = "yes"; }, "solver.warm_start",
       "expected true or false, got a string"},
      {[](json& s) { s["solver"]["sor"] = 2; }, "solver.sor", "must be strictly between 0 and 2"},
      {[](json& s) { s["solver"]["sor"] = 0; }, "solver.sor", "must be strictly between 0 and 2"},
      {[](json& s) { s["solver"]["substeps"] = 0; }, "solver.substeps", "must be an integer >= 1"},
      {[](json& s) { s["solver"]["post_stabilization"] = -1; }, "solver.post_stabilization",
       "must be an integer >= 0"},
      {[](json& s) { s["solver"]["post_stabilization"] = 1.5; }, "solver.post_stabilization",
       "must be an integer >= 0"},
      {[](json& s) { s["solver"]["projection"] = 1; }, "solver.projection",
       "expected true or false, got a number"},
      {[](json& s) { s["solver"]["geometric_stiffness"] = "on"; }, "solver.geometric_stiffness",
       "expected true or false, got a string"},
      {[](json& s) { s["solver"]["projection_iterations"] = 0; }, "solver.projection_iterations",
       "must be an integer >= 1"},
      {[](json& s) { s["solver"]["projection_tolerance"] = -1; }, "solver.projection_tolerance",
       "must be >= 0"},
  });
}

// A body without a mass takes it from its shapes' densities: two 1 m cubes of 1000 and 3000 kg/m^3
// side by side have their centre of mass at x = 0.25 (by moments: (1000 (-0.5) + 3000 (0.5)) /
// 4000); the body moves there and the shapes stay where they were in the world.
TEST(SceneReader, MassFromShapeDensities) {
  const linx::Scene scene = linx::parseScene(R"({
    "bodies": [{"name": "pair", "position": [1, 0, 0], "angular_velocity": [0, 0, 10], "shapes": [
      {"type": "box", "size": [1, 1, 1], "position": [-0.5, 0, 0], "density": 1000},
      {"type": "box", "size": [1, 1, 1], "position": [0.5, 0, 0], "density": 3000}]}]})",
                                             "scene.json");
  const linx::BodyDef& b = scene.bodies[0];
  EXPECT_DOUBLE_EQ(*b.mass, 4000.0);
  EXPECT_NEAR(b.position.x(), 1.25, 1e-12);
  EXPECT_NEAR(b.shapes[0].position.x(), -0.75, 1e-12);
  EXPECT_NEAR(b.shapes[1].position.x(), 0.25, 1e-12);
  // The stated velocity was the origin's; the centre, 0.25 m away, moves at w x 0.25 x.
  EXPECT_NEAR((b.linear_velocity - linx::Vec3(0, 2.5, 0)).norm(), 0.0, 1e-12);
  // Izz about the centre of mass: each cube m/6 plus m d^2 (d = 0.75 and 0.25).
  EXPECT_NEAR((*b.inertia)(2, 2), 1000.0 / 6 + 1000 * 0.5625 + 3000.0 / 6 + 3000 * 0.0625, 1e-9);
}

TEST(SceneReader, ContactAndSleepBlocks) {
  const linx::Scene scene = linx::parseScene(R"({
    "contact": {"margin": 0.02, "slop": 0.001, "stiffness": 1e5, "damping": 50,
                "restitution_threshold": 0.5},
    "sleep": {"enabled": false, "linear_velocity": 0.01, "angular_velocity": 0.02, "time": 1},
    "bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 1]}]})",
                                             "scene.json");
  const linx::ContactSettings& c = scene.settings.contact;
  EXPECT_EQ(c.margin, 0.02);
  EXPECT_EQ(c.slop, 0.001);
  EXPECT_EQ(c.stiffness, 1e5);
  EXPECT_EQ(c.damping, 50.0);
  EXPECT_EQ(c.restitution_threshold, 0.5);
  const linx::SleepSettings& z = scene.settings.sleep;
  EXPECT_FALSE(z.enabled);
  EXPECT_EQ(z.linear_velocity, 0.01);
  EXPECT_EQ(z.angular_velocity, 0.02);
  EXPECT_EQ(z.time, 1.0);
}

TEST(SceneError, ContactAndSleep) {
  expectErrors({
      {[](json& s) { s["contact"]["slop"] = -1; }, "contact.slop", "must be >= 0, got -1"},
      {[](json& s) { s["contact"]["stiffness"] = 1e4; }, "contact.damping",
       "missing required field (stiffness and damping go together)"},
      {[](json& s) { s["contact"] = json::parse(R"({"stiffness": 1, "damping": 1, "erp": 0.1})"); },
       "contact.erp", "give either erp and cfm, or stiffness and damping"},
      {[](json& s) { s["contact"]["marginn"] = 1; }, "contact.marginn",
       "unknown field (did you mean 'margin'?)"},
      {[](json& s) { s["sleep"]["time"] = -1; }, "sleep.time", "must be >= 0, got -1"},
      {[](json& s) { s["sleep"]["enabled"] = 1; }, "sleep.enabled",
       "expected true or false, got a number"},
  });
}

TEST(SceneError, Bodies) {
  expectErrors({
      {[](json& s) { s["bodies"][0] = 5; }, "bodies[0]", "expected an object, got a number"},
      {[](json& s) { s["bodies"][0]["mas"] = 1; }, "bodies[0].mas",
       "unknown field (did you mean 'mass'?)"},
      {[](json& s) { s["bodies"][0].erase("name"); }, "bodies[0].name", "missing required field"},
      {[](json& s) { s["bodies"][0]["name"] = 5; }, "bodies[0].name",
       "expected a string, got a number"},
      {[](json& s) { s["bodies"][0]["name"] = ""; }, "bodies[0].name", "must not be empty"},
      {[](json& s) { s["bodies"][0]["name"] = "world"; }, "bodies[0].name", "'world' is reserved"},
      {[](json& s) { s["bodies"][1]["name"] = "a"; }, "bodies[1].name",
       "duplicate body name 'a' (also bodies[0])"},
      {[](json& s) { s["bodies"][0].erase("mass"); }, "bodies[0].mass", "missing required field"},
      {[](json& s) {
         s["bodies"][0].erase("mass");
         s["bodies"][0]["shapes"] = json::parse(R"([{"type": "sphere", "radius": 1}])");
       },
       "bodies[0].shapes[0].density", "missing required field (the body gives no mass"},
      {[](json& s) {
         // 2 kg stated, 4189 kg from the density: one of them would be ignored.
         s["bodies"][0]["shapes"] =
             json::parse(R"([{"type": "sphere", "radius": 1, "density": 1000}])");
       },
       "bodies[0].mass", "2 kg, but the shapes' densities make 4188.79"},
      {[](json& s) { s["bodies"][0]["mass"] = 0; }, "bodies[0].mass", "must be > 0, got 0"},
      {[](json& s) { s["bodies"][0]["mass"] = -2; }, "bodies[0].mass", "must be > 0, got -2"},
      {[](json& s) { s["bodies"][1]["static"] = true, s["bodies"][1]["mass"] = 0; },
       "bodies[1].mass", "must be > 0"},
      {[](json& s) { s["bodies"][0].erase("inertia"); }, "bodies[0].inertia",
       "missing required field (give the inertia, or a shape to compute it from)"},
      {[](json& s) {
         s["bodies"][0]["inertia"] = {1, 0, 1};
       },
       "bodies[0].inertia[1]", "must be > 0, got 0"},
      {[](json& s) {
         s["bodies"][0]["inertia"] = {1, 2};
       },
       "bodies[0].inertia", "expected [Ixx, Iyy, Izz] or a 3x3 array, got 2 items"},
      {[](json& s) { s["bodies"][0]["inertia"] = 1; }, "bodies[0].inertia",
       "expected [Ixx, Iyy, Izz] or a 3x3 array, got a number"},
      {[](json& s) { s["bodies"][0]["inertia"] = json::parse("[[1,0.5,0],[0,1,0],[0,0,1]]"); },
       "bodies[0].inertia", "must be symmetric"},
      {[](json& s) { s["bodies"][0]["inertia"] = json::parse("[[1,2,0],[2,1,0],[0,0,1]]"); },
       "bodies[0].inertia", "must be positive definite"},
      {[](json& s) { s["bodies"][0]["inertia"] = json::parse("[[1,0],[0,1,0],[0,0,1]]"); },
       "bodies[0].inertia[0]", "expected an array of 3 numbers, got 2 items"},
      {[](json& s) {
         s["bodies"][0]["orientation"] = {0, 0, 0, 0};
       },
       "bodies[0].orientation", "must not be zero"},
      {[](json& s) {
         s["bodies"][0]["orientation"] = {1, 0, 0};
       },
       "bodies[0].orientation", "expected an array of 4 numbers, got 3 items"},
      {[](json& s) {
         s["bodies"][0]["position"] = {0, 0, nullptr};
       },
       "bodies[0].position[2]", "expected a number, got null"},
      {[](json& s) {
         s["bodies"][0]["linear_velocity"] = {0, 0};
       },
       "bodies[0].linear_velocity", "expected an array of 3 numbers"},
      {[](json& s) { s["bodies"][0]["static"] = "true"; }, "bodies[0].static",
       "expected true or false, got a string"},
      {[](json& s) {
         s["bodies"][0]["static"] = true, s["bodies"][0]["angular_velocity"] = {0, 1, 0};
       },
       "bodies[0].angular_velocity", "a static body cannot move"},
      {[](json& s) { s["bodies"][0]["shapes"] = json::object(); }, "bodies[0].shapes",
       "expected an array, got an object"},
  });
}

TEST(SceneError, Shapes) {
  const auto shape = [](const char* text) {
    return [text](json& s) { s["bodies"][1]["shapes"][0] = json::parse(text); };
  };
  expectErrors({
      {shape(R"(1)"), "bodies[1].shapes[0]", "expected an object, got a number"},
      {shape(R"({"radius": 1})"), "bodies[1].shapes[0].type", "missing required field"},
      {shape(R"({"type": "cone"})"), "bodies[1].shapes[0].type",
       "unknown shape type 'cone' (expected sphere, box, capsule, cylinder, ellipsoid, plane, "
       "convex or "
       "mesh)"},
      {shape(R"({"type": "sphere", "radious": 1})"), "bodies[1].shapes[0].radious",
       "unknown field (did you mean 'radius'?)"},
      {shape(R"({"type": "sphere"})"), "bodies[1].shapes[0].radius", "missing required field"},
      {shape(R"({"type": "sphere", "radius": 0})"), "bodies[1].shapes[0].radius",
       "must be > 0, got 0"},
      {shape(R"({"type": "sphere", "radius": 1, "size": [1, 1, 1]})"), "bodies[1].shapes[0].size",
       "not used by a sphere shape"},
      {shape(R"({"type": "box", "radius": 1})"), "bodies[1].shapes[0].radius",
       "not used by a box shape"},
      {shape(R"({"type": "box"})"), "bodies[1].shapes[0].size", "missing required field"},
      {shape(R"({"type": "box", "size": [1, -1, 1]})"), "bodies[1].shapes[0].size[1]",
       "must be > 0, got -1"},
      {shape(R"({"type": "capsule", "radius": 1})"), "bodies[1].shapes[0].length",
       "missing required field"},
      {shape(R"({"type": "capsule", "radius": 1, "length": -1})"), "bodies[1].shapes[0].length",
       "must be >= 0, got -1"},
      {shape(R"({"type": "cylinder", "radius": 1, "length": 0})"), "bodies[1].shapes[0].length",
       "must be > 0, got 0"},
      {shape(R"({"type": "sphere", "radius": 1, "orientation": [0, 0, 0, 0]})"),
       "bodies[1].shapes[0].orientation", "must not be zero"},
      {shape(R"({"type": "sphere", "radius": 1, "friction": -0.1})"),
       "bodies[1].shapes[0].friction", "must be >= 0, got -0.1"},
      {shape(R"({"type": "sphere", "radius": 1, "restitution": 1.5})"),
       "bodies[1].shapes[0].restitution", "must be between 0 and 1, got 1.5"},
      {shape(R"({"type": "sphere", "radius": 1, "group": 1.5})"), "bodies[1].shapes[0].group",
       "must be an integer in [0, 4294967295]"},
      {shape(R"({"type": "plane", "normal": [0, 0, 1]})"), "bodies[1].shapes[0].type",
       "a plane belongs on a static body"},
      {shape(R"({"type": "plane", "radius": 1})"), "bodies[1].shapes[0].radius",
       "not used by a plane shape"},
      {shape(R"({"type": "convex", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})"),
       "bodies[1].shapes[0].points", "needs at least 4 points, got 3"},
      {shape(R"({"type": "mesh", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                 "triangles": [[0, 1, 3]]})"),
       "bodies[1].shapes[0].triangles[0][2]", "must be a point index in [0, 3), got 3"},
      {shape(R"({"type": "mesh", "file": "no_such_terrain.obj"})"), "bodies[1].shapes[0].file",
       "no_such_terrain.obj"},
      {shape(R"({"type": "mesh", "file": ""})"), "bodies[1].shapes[0].file", "must not be empty"},
      {shape(R"({"type": "convex", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]})"),
       "bodies[1].shapes[0].points", "convex: all 4 points lie in one plane"},
      {shape(
           R"({"type": "convex", "points": [[0, 0, 0], [1e-9, 0, 0], [0, 1e9, 0], [0, 0, 1e9]]})"),
       "bodies[1].shapes[0].points",
       "convex: the hull is 1.41e+09 m across but only 1e-09 m thick, a spread of 18 orders of "
       "magnitude (at most 9)"},
      {shape(R"({"type": "convex",
                 "points": [[1e300, 0, 0], [-1e300, 0, 0], [0, 1e300, 0], [0, 0, 1e300]]})"),
       "bodies[1].shapes[0].points",
       "convex: point 0 has a coordinate of 1e+300 m, too large (at most 1e+50 m: the hull's "
       "volume and inertia would overflow)"},
      {shape(R"({"type": "mesh", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                 "triangles": [[0, 1, 1]]})"),
       "bodies[1].shapes[0].triangles[0]", "repeats point 1"},
      {shape(R"({"type": "mesh", "points": [[1e300, 0, 0], [-1e300, 0, 0], [0, 1e300, 0]],
                 "triangles": [[0, 1, 2]]})"),
       "bodies[1].shapes[0].points",
       "mesh: vertex 0 has a coordinate of 1e+300 m, too large (at most 1e+50 m: triangle areas "
       "would overflow)"},
  });
}

TEST(SceneError, Joints) {
  const auto joint = [](const char* text) {
    return [text](json& s) { s["joints"][0] = json::parse(text); };
  };
  expectErrors({
      {joint(R"("h")"), "joints[0]", "expected an object, got a string"},
      {[](json& s) {
         s["joints"][0]["axsi"] = {0, 0, 1};
       },
       "joints[0].axsi", "unknown field (did you mean 'axis'?)"},
      {[](json& s) { s["joints"][0].erase("name"); }, "joints[0].name", "missing required field"},
      {[](json& s) { s["joints"][0]["name"] = ""; }, "joints[0].name", "must not be empty"},
      {[](json& s) { s["joints"][1] = s["joints"][0]; }, "joints[1].name",
       "duplicate joint name 'h' (also joints[0])"},
      {[](json& s) { s["joints"][0].erase("type"); }, "joints[0].type", "missing required field"},
      {[](json& s) { s["joints"][0]["type"] = "cardan"; }, "joints[0].type",
       "unknown joint type 'cardan' (expected fixed, slider, hinge, ball, universal, cylindrical, "
       "hinge2, distance, cone_twist, planar, gear, generic, spring, rack_and_pinion, serial or "
       "mimic)"},
      // The hinge's axis is the first problem in the file: a universal joint takes axis1 and axis2.
      {[](json& s) { s["joints"][0]["type"] = "universal"; }, "joints[0].axis",
       "not used by a universal joint"},
      {[](json& s) {
         s["joints"][0]["type"] = "universal";
         s["joints"][0].erase("axis");
       },
       "joints[0].axis1", "missing required field"},
      {[](json& s) {
         s["joints"][0]["locked"] = true;
         s["joints"][0]["armature"] = 0.1;
       },
       "joints[0].locked",
       "a locked coordinate takes no limits, motor, spring, friction, armature or force"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a"})"), "joints[0].axes",
       "missing required field"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a", "axes": []})"), "joints[0].axes",
       "a serial joint has 1 to 6 axes, not 0"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a",
                 "axes": [{"type": "ball", "axis": [0,0,1]}]})"),
       "joints[0].axes[0].type", "unknown axis type 'ball' (expected hinge or slider)"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a",
                 "axes": [{"type": "slider", "axis": [0,0,1], "anchor": [0,0,0]}]})"),
       "joints[0].axes[0].anchor", "not used by a slider axis"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a",
                 "axes": [{"type": "hinge", "axis": [0,0,1]}]})"),
       "joints[0].axes[0].anchor", "missing required field"},
      {joint(R"({"name": "s", "type": "serial", "body1": "a", "limits": {"lower": 0},
                 "axes": [{"type": "slider", "axis": [0,0,1]}]})"),
       "joints[0].limits", "not used by a serial joint"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0]})"),
       "joints[0].axis2", "missing required field"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0], "axis2": [1,1,0]})"),
       "joints[0].axis2", "must be perpendicular to axis1 (they are 45 deg apart)"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0], "axis2": [0,1,0], "axis": [0,0,1]})"),
       "joints[0].axis", "not used by a universal joint"},
      {joint(R"({"name": "h", "type": "hinge", "body1": "a", "anchor": [0,0,0],
                 "axis": [1,0,0], "axis2": [0,1,0]})"),
       "joints[0].axis2", "not used by a hinge joint"},
      {[](json& s) { s["joints"][0].erase("body1"); }, "joints[0].body1", "missing required field"},
      {[](json& s) { s["joints"][0]["body1"] = "c"; }, "joints[0].body1", "unknown body 'c'"},
      {[](json& s) { s["joints"][0]["body1"] = "aa"; }, "joints[0].body1",
       "unknown body 'aa' (did you mean 'a'?)"},
      {[](json& s) { s["joints"][0]["body1"] = 0; }, "joints[0].body1",
       "expected a string, got a number"},
      {[](json& s) { s["joints"][0]["body1"] = "world"; }, "joints[0].body1",
       "must be a body, not the world"},
      {[](json& s) { s["joints"][0]["body2"] = "bee"; }, "joints[0].body2", "unknown body 'bee'"},
      {[](json& s) { s["joints"][0]["body2"] = "a"; }, "joints[0].body2",
       "a joint needs two different bodies"},
      {[](json& s) { s["joints"][0].erase("anchor"); }, "joints[0].anchor",
       "missing required field"},
      {joint(R"({"name": "p", "type": "ball", "body1": "a"})"), "joints[0].anchor",
       "missing required field"},
      {[](json& s) { s["joints"][0].erase("axis"); }, "joints[0].axis", "missing required field"},
      {joint(R"({"name": "s", "type": "slider", "body1": "a"})"), "joints[0].axis",
       "missing required field"},
      {[](json& s) {
         s["joints"][0]["axis"] = {0, 0, 0};
       },
       "joints[0].axis", "must not be zero"},
      {joint(R"({"name": "p", "type": "ball", "body1": "a", "anchor": [0,0,0], "axis": [0,0,1]})"),
       "joints[0].axis", "not used by a ball joint"},
      {joint(R"({"name": "f", "type": "fixed", "body1": "a", "limits": {"upper": 1}})"),
       "joints[0].limits", "not used by a fixed joint"},
      {joint(R"({"name": "p", "type": "ball", "body1": "a", "anchor": [0,0,0],
                 "motor": {"max_force": 1}})"),
       "joints[0].motor", "not used by a ball joint"},
      {[](json& s) {
         s["joints"][0]["limits"] = {{"lower", 1}, {"upper", -1}};
       },
       "joints[0].limits", "lower (1) is above upper (-1)"},
      {[](json& s) {
         s["joints"][0]["limits"] = {{"min", 1}};
       },
       "joints[0].limits.min", "unknown field"},
      {[](json& s) {
         s["joints"][0]["limits"] = {{"lower", "a"}};
       },
       "joints[0].limits.lower", "expected a number, got a string"},
      {[](json& s) {
         s["joints"][0]["limits"] = {1, 2};
       },
       "joints[0].limits", "expected an object, got an array"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_velocity", 1}};
       },
       "joints[0].motor.max_force", "missing required field"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"max_force", -1}};
       },
       "joints[0].motor.max_force", "must be >= 0, got -1"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_position", 1}};
       },
       "joints[0].motor.stiffness", "a servo (target_position) needs a stiffness > 0"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"stiffness", 10}, {"max_force", 1}};
       },
       "joints[0].motor.target_position", "a stiffness pulls towards a target_position"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_position", 1}, {"stiffness", -10}};
       },
       "joints[0].motor.stiffness", "must be >= 0, got -10"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_position", 1}, {"stiffness", 10}, {"gain", 1}};
       },
       "joints[0].motor.gain", "unknown field"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_position", {{"times", {0, 1}}, {"values", {0}}}},
                                    {"stiffness", 1}};
       },
       "joints[0].motor.target_position.values", "1 values for 2 times"},
      {[](json& s) {
         s["joints"][0]["motor"] = {
             {"target_position", {{"times", {0, 2, 1}}, {"values", {0, 1, 2}}}}, {"stiffness", 1}};
       },
       "joints[0].motor.target_position.times[2]", "must be after the time before it (1 <= 2)"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_position", "up"}, {"stiffness", 1}};
       },
       "joints[0].motor.target_position", "expected a number or a table"},
      {[](json& s) {
         s["joints"][0]["motor"] = {{"target_velocity", {{"file", "nowhere.csv"}}},
                                    {"max_force", 1}};
       },
       "joints[0].motor.target_velocity.file", "cannot read"},
      {[](json& s) {
         s["joints"][0]["spring"] = {{"rest", 1}};
       },
       "joints[0].spring", "needs a stiffness, a damping or both"},
      {[](json& s) {
         s["joints"][0]["spring"] = {{"stiffness", 1}, {"damping", -2}};
       },
       "joints[0].spring.damping", "must be >= 0, got -2"},
      {[](json& s) {
         s["joints"][0]["spring"] = {{"stiffness", 1}, {"length", 2}};
       },
       "joints[0].spring.length", "unknown field"},
      {joint(R"({"name": "f", "type": "fixed", "body1": "a", "spring": {"stiffness": 1}})"),
       "joints[0].spring", "not used by a fixed joint"},
      {[](json& s) { s["joints"][0]["friction"] = -1; }, "joints[0].friction", "must be >= 0"},
      {joint(R"({"name": "c", "type": "cone_twist", "body1": "a", "anchor": [0, 0, 0],
                 "axis1": [0, 0, 1], "axis2": [1, 0, 0], "cone": {"swing1": 4, "swing2": 1}})"),
       "joints[0].cone.swing1", "must be in (0, pi) rad, got 4"},
      {joint(R"({"name": "c", "type": "cone_twist", "body1": "a", "anchor": [0, 0, 0],
                 "axis1": [0, 0, 1], "axis2": [1, 0, 0], "cone": {"swing1": 1}})"),
       "joints[0].cone.swing2", "missing required field"},
      {[](json& s) {
         s["joints"][0]["cone"] = {{"swing1", 1}, {"swing2", 1}};
       },
       "joints[0].cone", "not used by a hinge joint"},
      {joint(R"({"name": "g", "type": "generic", "body1": "a", "anchor": [0, 0, 0],
                 "axis1": [1, 0, 0], "axis2": [0, 1, 0], "rz": {"locked": true, "friction": 1}})"),
       "joints[0].rz.locked",
       "a locked coordinate takes no limits, motor, spring, friction, armature or force"},
      {[](json& s) {
         s["joints"][0]["prescribed"] = {{"times", {0, 1}}, {"values", {0, 1}}};
         s["joints"][0]["friction"] = 1;
       },
       "joints[0].prescribed", "a prescribed coordinate takes no limits, motor, spring"},
      {[](json& s) { s["joints"][0]["break_force"] = 0; }, "joints[0].break_force", "must be > 0"},
      {[](json& s) { s["joints"][0]["prescribed"] = "fast"; }, "joints[0].prescribed",
       "expected a number or a table"},
      {joint(R"({"name": "d", "type": "distance", "body1": "a"})"), "joints[0].anchor2",
       "missing required field (the point held in the world)"},
      {joint(R"({"name": "d", "type": "distance", "body1": "a", "anchor2": [1, 0, 0]})"),
       "joints[0].anchor2", "the two points must be apart at the start (0 m"},
      {joint(R"({"name": "d", "type": "distance", "body1": "a", "anchor2": [0, 0, 0],
                 "length": 0})"),
       "joints[0].length", "must be > 0"},
      {joint(R"({"name": "d", "type": "distance", "body1": "a", "anchor2": [0, 0, 0],
                 "anchor": [0, 0, 0]})"),
       "joints[0].anchor", "not used by a distance joint"},
      {joint(R"({"name": "h", "type": "hinge", "body1": "a", "anchor": [0, 0, 0],
                 "axis": [0, 0, 1], "rope": true})"),
       "joints[0].rope", "not used by a hinge joint"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0], "axis2": [0,1,0], "limits": {"upper": 1}})"),
       "joints[0].limits",
       "a universal joint has 2 coordinates: give it in one of them (angle1.limits)"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0], "axis2": [0,1,0], "angle2": {"stiffness": 1}})"),
       "joints[0].angle2.stiffness", "unknown field"},
      {joint(R"({"name": "u", "type": "universal", "body1": "a", "anchor": [0,0,0],
                 "axis1": [1,0,0], "axis2": [0,1,0], "angle1": {"friction": -2}})"),
       "joints[0].angle1.friction", "must be >= 0"},
      {joint(R"({"name": "h", "type": "hinge", "body1": "a", "anchor": [0,0,0],
                 "axis": [1,0,0], "angle1": {}})"),
       "joints[0].angle1", "unknown field"},
      {[](json& s) { s["joints"][0]["erp"] = 2; }, "joints[0].erp", "must be between 0 and 1"},
      {[](json& s) { s["joints"][0]["cfm"] = -1; }, "joints[0].cfm", "must be >= 0"},
  });
}

TEST(SceneRead, EachCoordinateOfAUniversalJoint) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "u", "type": "universal", "body1": "a",
      "anchor": [0, 0, 0], "axis1": [1, 0, 0], "axis2": [0, 1, 0],
      "angle1": {"limits": {"lower": -0.5}, "friction": 0.25},
      "angle2": {"spring": {"stiffness": 3}, "motor": {"target_velocity": 1, "max_force": 2}}})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  ASSERT_TRUE(d.coordinates[0].limits);
  EXPECT_EQ(d.coordinates[0].limits->lower, -0.5);
  EXPECT_EQ(d.coordinates[0].friction, 0.25);
  EXPECT_FALSE(d.coordinates[0].motor || d.coordinates[0].spring);
  ASSERT_TRUE(d.coordinates[1].spring && d.coordinates[1].motor);
  EXPECT_EQ(d.coordinates[1].spring->stiffness, 3.0);
  EXPECT_EQ(d.coordinates[1].motor->max_force, 2.0);
  EXPECT_TRUE(d.coordinates[2].empty());
}

TEST(SceneRead, GenericJointLocksAndFreesEachAxis) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "g", "type": "generic", "body1": "a",
      "anchor": [0, 0, 0], "axis1": [1, 0, 0], "axis2": [0, 1, 0],
      "x": {"locked": true}, "y": {"limits": {"lower": -1, "upper": 1}}, "rz": {"locked": false}})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  EXPECT_TRUE(d.coordinates[0].locked);
  EXPECT_FALSE(d.coordinates[1].locked);
  EXPECT_EQ(d.coordinates[1].limits->upper, 1.0);
  EXPECT_TRUE(d.coordinates[2].empty());  // free: nothing acts on it
  EXPECT_TRUE(d.coordinates[5].empty());
}

TEST(SceneRead, BreakableJoint) {
  json scene = baseScene();
  scene["joints"][0]["break_force"] = 250;
  scene["joints"][0]["break_torque"] = 12.5;
  const linx::JointDef d = parse(scene).joints.at(0).def;
  EXPECT_EQ(d.break_force, 250.0);
  EXPECT_EQ(d.break_torque, 12.5);
}

TEST(SceneRead, PrescribedCoordinate) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "u", "type": "universal", "body1": "a",
      "anchor": [0, 0, 0], "axis1": [1, 0, 0], "axis2": [0, 1, 0],
      "angle2": {"prescribed": {"times": [0, 2], "values": [0, 1]}}})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  EXPECT_TRUE(d.coordinates[0].empty());
  ASSERT_TRUE(d.coordinates[1].prescribed);
  EXPECT_EQ(d.coordinates[1].prescribed->at(1.0), 0.5);
}

TEST(SceneRead, ConeTwistJoint) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "c", "type": "cone_twist", "body1": "a",
      "anchor": [0, 0, 0], "axis1": [0, 0, -1], "axis2": [1, 0, 0],
      "cone": {"swing1": 0.5, "swing2": 0.25}, "limits": {"lower": -1, "upper": 1}})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  ASSERT_TRUE(d.cone);
  EXPECT_EQ(d.cone->swing1, 0.5);
  EXPECT_EQ(d.cone->swing2, 0.25);
  EXPECT_EQ(d.coordinates[0].limits->lower, -1.0);  // the twist's (its one free coordinate)
}

TEST(SceneRead, GearJoint) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "g", "type": "gear", "body1": "a", "body2": "b",
      "axis1": [0, 0, 1], "axis2": [1, 0, 0], "ratio": -0.5})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  EXPECT_EQ(d.ratio, -0.5);
  EXPECT_EQ(d.axis2, linx::Vec3(1, 0, 0));  // bevel gears: the axles need not be perpendicular
  scene["joints"][0]["ratio"] = 0;
  EXPECT_EQ(errorOf(scene.dump()).field(), "joints[0].ratio");
  scene["joints"][0].erase("ratio");
  EXPECT_EQ(errorOf(scene.dump()).field(), "joints[0].ratio");
}

TEST(SceneRead, DistanceJoint) {
  json scene = baseScene();
  scene["joints"][0] = json::parse(R"({"name": "r", "type": "distance", "body1": "a",
      "body2": "b", "anchor2": [0, 0, 1], "length": 2.5, "rope": true})");
  const linx::JointDef d = parse(scene).joints.at(0).def;
  EXPECT_EQ(*d.anchor, linx::Vec3(1, 0, 0));  // body a's position
  EXPECT_EQ(*d.anchor2, linx::Vec3(0, 0, 1));
  EXPECT_EQ(*d.length, 2.5);
  EXPECT_TRUE(d.rope);
}

TEST(SceneRead, TargetsInTime) {
  json scene = baseScene();
  scene["joints"][0]["motor"] = {
      {"target_position", {{"times", {0, 1, 2.5}}, {"values", {0, 0.5, -1}}}}, {"stiffness", 100}};
  const linx::JointMotor m = *parse(scene).joints.at(0).def.coordinates[0].motor;
  EXPECT_EQ(m.target_position->times, (std::vector<double>{0, 1, 2.5}));
  EXPECT_EQ(m.target_position->values, (std::vector<double>{0, 0.5, -1}));
  EXPECT_EQ(m.target_position->at(1.75), -0.25);
  // From a CSV file beside the scene, with a header line.
  const auto dir = std::filesystem::temp_directory_path() / "linx_targets_in_time";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "speed.csv") << "time,speed\r\n0,0\r\n2,4\r\n3,4\r\n";
  scene["joints"][0]["motor"] = {{"target_velocity", {{"file", "speed.csv"}}}, {"max_force", 5}};
  const linx::Scene read = linx::parseScene(scene.dump(), (dir / "scene.json").string());
  const linx::Signal& v = read.joints.at(0).def.coordinates[0].motor->target_velocity;
  EXPECT_EQ(v.times, (std::vector<double>{0, 2, 3}));
  EXPECT_EQ(v.at(1.0), 2.0);
  std::ofstream(dir / "bad.csv") << "0,0\n1,x\n";
  scene["joints"][0]["motor"] = {{"target_velocity", {{"file", "bad.csv"}}}, {"max_force", 5}};
  try {
    linx::parseScene(scene.dump(), (dir / "scene.json").string());
    ADD_FAILURE() << "bad.csv accepted";
  } catch (const linx::SceneError& e) {
    EXPECT_EQ(e.field(), "joints[0].motor.target_velocity.file");
    EXPECT_NE(e.problem().find("bad.csv line 2: expected two numbers, time and value, got '1,x'"),
              std::string::npos)
        << e.problem();
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneRead, DrivesAndSprings) {
  json scene = baseScene();
  scene["joints"][0]["motor"] = {
      {"target_position", 0.5}, {"stiffness", 1e4}, {"damping", 20}, {"max_force", 30}};
  scene["joints"][0]["spring"] = {{"stiffness", 5}, {"damping", 0.1}, {"rest", -0.2}};
  const linx::Scene s = parse(scene);
  const linx::JointDef& d = s.joints.at(0).def;
  ASSERT_TRUE(d.coordinates[0].motor && d.coordinates[0].spring);
  EXPECT_EQ(d.coordinates[0].motor->target_position, 0.5);
  EXPECT_EQ(d.coordinates[0].motor->stiffness, 1e4);
  EXPECT_EQ(d.coordinates[0].motor->damping, 20.0);
  EXPECT_EQ(d.coordinates[0].motor->max_force, 30.0);
  EXPECT_EQ(d.coordinates[0].motor->target_velocity, 0.0);
  EXPECT_EQ(d.coordinates[0].spring->stiffness, 5.0);
  EXPECT_EQ(d.coordinates[0].spring->damping, 0.1);
  EXPECT_EQ(d.coordinates[0].spring->rest, -0.2);
  // A servo and a damped motor need no bound; a velocity motor still does (errors above).
  scene["joints"][0]["motor"] = {{"target_position", 0.5}, {"stiffness", 1e4}};
  EXPECT_EQ(parse(scene).joints.at(0).def.coordinates[0].motor->max_force, linx::kInfinity);
  scene["joints"][0]["motor"] = {{"target_velocity", 2}, {"damping", 3}};
  const linx::JointMotor damped = *parse(scene).joints.at(0).def.coordinates[0].motor;
  EXPECT_TRUE(damped.isServo());
  EXPECT_EQ(damped.max_force, linx::kInfinity);
}

}  // namespace

namespace {
// A hostile file nested 100,000 deep is refused while it is read (a clear error, no stack
// overflow copying it), at the first level past the bound.
TEST(SceneError, DeepNestingIsRefusedAtItsDepth) {
  const std::string deep = std::string(100000, '[') + "1" + std::string(100000, ']');
  const linx::SceneError e = errorOf(R"({"bodies": [{"name": "b", "mass": )" + deep + "}]}");
  EXPECT_EQ(e.problem(), "nested deeper than 256 levels of arrays and objects");
  EXPECT_EQ(e.field().rfind("bodies[0].mass[0][0]", 0), 0u);
}
}  // namespace

namespace {
// An object of a million fields would be read by linear searches for hours: refused at the first
// past 4096.
TEST(SceneError, ObjectsOfThousandsOfFieldsAreRefused) {
  std::string wide = "{";
  for (int i = 0; i < 5000; ++i) wide += (i ? ", \"k" : "\"k") + std::to_string(i) + "\": 1";
  wide += "}";
  const linx::SceneError e = errorOf(R"({"bodies": [{"name": "b", "mass": )" + wide + "}]}");
  EXPECT_EQ(e.problem(), "more than 4096 fields in one object");
  EXPECT_EQ(e.field(), "bodies[0].mass.k4096");
}
}  // namespace
