// The scene format described once (linx/schema.hpp, src/schema/describe.hpp): the reader, the
// writer, the C++ checks and the docs' tables follow the same description. Each field's bounds
// are refused alike by a scene file and by the C++ API, errors come in the file's order, a
// misspelt field is pointed to the one meant (other engines' names too), every record survives a
// write and a read to the bit, and docs/scene-format.md shows the tables the description makes.
#include <linx/joint.hpp>
#include <linx/scene.hpp>
#include <linx/schema.hpp>
#include <linx/world.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "schema/describe.hpp"

namespace linx {
namespace {

using json = nlohmann::ordered_json;

json baseScene() {
  return json::parse(R"({
    "bodies": [{"name": "a", "mass": 2, "inertia": [1, 2, 3]}],
    "joints": [{"name": "h", "type": "hinge", "body1": "a", "anchor": [0, 0, 0],
                "axis": [0, 0, 1]}]
  })");
}

// "FIELD: PROBLEM" of the error reading `scene`, or "accepted".
std::string errorOf(const json& scene) {
  try {
    parseScene(scene.dump(), "s.json");
  } catch (const SceneError& e) {
    return e.field() + ": " + e.problem();
  }
  return "accepted";
}

// A number just outside the range's lower or upper end (none where that end is unbounded); an
// integer for an integer field.
std::optional<double> outside(const schema::Range& r, bool below, bool integer) {
  const double end = below ? r.lower : r.upper;
  if (!std::isfinite(end)) return std::nullopt;
  const bool open = below ? r.lower_open : r.upper_open;
  if (open) return end;
  const double step = integer ? 1.0 : 0.5;
  return below ? end - step : end + step;
}

// Sets the field `name` of a described record to `value` (numbers only).
class Assign {
 public:
  Assign(std::string_view name, double value) : name_(name), value_(value) {}
  void field(double& x, const schema::FieldInfo& info) {
    if (info.name == name_) x = value_;
  }
  void field(int& x, const schema::FieldInfo& info) {
    if (info.name == name_) x = static_cast<int>(value_);
  }
  void field(std::optional<double>& x, const schema::FieldInfo& info) {
    if (info.name == name_) x = value_;
  }
  template <class T>
  void field(T&, const schema::FieldInfo&) {}

 private:
  std::string_view name_;
  double value_;
};

// `value` set from C++ into the named section's field: what World::step says of it.
std::string apiError(const std::string& section, std::string_view field, double value) {
  World world;
  BodyDef body;
  body.name = "a";
  body.mass = 1.0;
  body.inertia = Mat3::Identity();
  world.createBody(body);
  WorldSettings& s = world.settings();
  Assign assign(field, value);
  if (section == "solver") schema::describe(assign, s.solver);
  if (section == "integrator") schema::describe(assign, s.integrator);
  if (section == "contact") schema::describe(assign, s.contact);
  if (section == "sleep") schema::describe(assign, s.sleep);
  if (section == "faults") schema::describe(assign, s.faults);
  // A contact stiffness goes with a damping (the record's rule, not this field's bounds).
  if (section == "contact" && (field == "stiffness" || field == "damping")) {
    if (!s.contact.stiffness) s.contact.stiffness = 1e4;
    if (!s.contact.damping) s.contact.damping = 10.0;
  }
  try {
    world.step();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

// Every numeric field of the settings sections, at a value just outside its bounds: the file is
// refused naming the field, and World::step refuses the same value set from C++ in the same
// words.
TEST(Schema, FileAndApiRefuseTheSameValuesInTheSameWords) {
  int checked = 0;
  for (const std::string section : {"solver", "integrator", "contact", "sleep", "faults"}) {
    const schema::Record* record = schema::findRecord(section);
    ASSERT_NE(record, nullptr) << section;
    for (const schema::Field& f : record->fields) {
      const bool integer = f.type.rfind("integer", 0) == 0;
      if (!(f.type.rfind("number", 0) == 0 || integer)) continue;
      for (const bool below : {true, false}) {
        const auto bad = outside(f.info.range, below, integer);
        if (!bad) continue;
        json scene = baseScene();
        scene[section][std::string(f.info.name)] = *bad;
        if (section == "contact" && (f.info.name == "stiffness" || f.info.name == "damping")) {
          scene[section]["stiffness"] = f.info.name == "stiffness" ? *bad : 1e4;
          scene[section]["damping"] = f.info.name == "damping" ? *bad : 10.0;
        }
        const std::string path = section + "." + std::string(f.info.name);
        const std::string expected = path + ": " + f.info.range.problem(*bad, integer);
        EXPECT_EQ(errorOf(scene), expected);
        EXPECT_EQ(apiError(section, f.info.name, *bad), expected);
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 25);
}

// The first problem in the file is the one reported, whatever the fields' names.
TEST(Schema, ErrorsComeInTheFilesOrder) {
  json a = baseScene();
  a["solver"] = json::parse(R"({"sor": 5, "erp": 7})");
  EXPECT_EQ(errorOf(a), "solver.sor: must be strictly between 0 and 2, got 5");
  json b = baseScene();
  b["solver"] = json::parse(R"({"erp": 7, "sor": 5})");
  EXPECT_EQ(errorOf(b), "solver.erp: must be between 0 and 1, got 7");
  json c = baseScene();
  c["sleep"] = json::parse(R"({"tyme": 1, "enabled": 3})");
  EXPECT_EQ(errorOf(c), "sleep.tyme: unknown field (did you mean 'time'?)");
  json d = baseScene();
  d["joints"][0]["motor"] = json::parse(R"({"max_force": -1, "target_velocity": "x"})");
  EXPECT_EQ(errorOf(d), "joints[0].motor.max_force: must be >= 0, got -1");
}

// A misspelt field, at any depth, is pointed to the one meant; other engines' names for it too.
TEST(Schema, MisspeltFieldsAreNamedWithTheClosest) {
  const auto nested = [](const char* key, const char* part) {
    json scene = baseScene();
    scene["joints"][0][key] = json::parse(part);
    return errorOf(scene);
  };
  EXPECT_EQ(nested("motor", R"({"target_velocity": 1, "max_torque": 2})"),
            "joints[0].motor.max_torque: unknown field (did you mean 'max_force'?)");
  EXPECT_EQ(nested("motor", R"({"velocity": 1, "max_force": 2})"),
            "joints[0].motor.velocity: unknown field (did you mean 'target_velocity'?)");
  EXPECT_EQ(nested("limits", R"({"min": -1, "max": 1})"),
            "joints[0].limits.min: unknown field (did you mean 'lower'?)");
  EXPECT_EQ(nested("limits", R"({"lower": -1, "uper": 1})"),
            "joints[0].limits.uper: unknown field (did you mean 'upper'?)");
  EXPECT_EQ(nested("spring", R"({"kp": 10})"),
            "joints[0].spring.kp: unknown field (did you mean 'stiffness'?)");
  json scene = baseScene();
  scene["contact"] = json::parse(R"({"marjin": 0.1})");
  EXPECT_EQ(errorOf(scene), "contact.marjin: unknown field (did you mean 'margin'?)");
}

// Every settings record, each field away from its default, written and read back to the bit.
TEST(Schema, SettingsSurviveAWriteAndARead) {
  Scene scene = parseScene(baseScene().dump(), "s.json");
  WorldSettings& s = scene.settings;
  s.solver = {SolverType::Pgs, 17, 3e-9, 0.35, 2e-7, false, 1.3, 2, 7, true, 5, 1e-11, false};
  s.integrator = {IntegratorType::Accurate, 3e-8};
  s.contact.enabled = false;
  s.contact.margin = 0.02;
  s.contact.slop = 1e-3 / 3.0;
  s.contact.stiffness = 2e5;
  s.contact.damping = 300.0;
  s.contact.restitution_threshold = 0.1;
  s.contact.max_push_out = 2.5;
  s.contact.hertz = 30.0;
  s.contact.damping_ratio = 4.0;
  s.sleep = {false, 0.01, 0.02, 1.25};
  s.faults.max_speed = 50.0;
  s.faults.max_angular_speed = 60.0;
  s.faults.max_joint_error = 0.5;
  s.faults.joint_error_every = 3;
  s.faults.energy = false;
  s.faults.kinetic_fraction = 0.25;
  s.faults.height = 0.2;
  s.faults.speed = 1.5;
  scene.view = SceneView{Vec3(3, 4, 5), Vec3(0, 0, 0.5), Vec3(0, 0.6, 0.8), 55.0};
  const Scene back = parseScene(writeSceneJson(scene), "back.json");
  const WorldSettings& b = back.settings;
  EXPECT_EQ(writeSceneJson(back), writeSceneJson(scene));
  EXPECT_EQ(b.solver.type, SolverType::Pgs);
  EXPECT_EQ(b.solver.projection_tolerance, 1e-11);
  EXPECT_EQ(b.integrator.tolerance, 3e-8);
  EXPECT_EQ(b.contact.slop, 1e-3 / 3.0);
  EXPECT_EQ(*b.contact.damping, 300.0);
  EXPECT_EQ(b.sleep.time, 1.25);
  EXPECT_EQ(b.faults.joint_error_every, 3);
  ASSERT_TRUE(back.view && back.view->up);
  EXPECT_EQ(*back.view->up, Vec3(0, 0.6, 0.8).normalized());
}

// A joint of type `t` between bodies a and b with every field its type takes (after two hinges
// for a mimic joint to tie), as JSON.
json jointScene(const JointTypeInfo& t) {
  json scene = json::parse(R"({
    "bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1], "position": [1, 0, 0]},
               {"name": "b", "mass": 1, "inertia": [1, 1, 1]}],
    "joints": [
      {"name": "h1", "type": "hinge", "body1": "a", "anchor": [0, 0, 0], "axis": [0, 0, 1]},
      {"name": "h2", "type": "hinge", "body1": "b", "body2": "a", "anchor": [1, 0, 0],
       "axis": [0, 0, 1]}]
  })");
  json j = {{"name", "j"}, {"type", std::string(t.name)}};
  if (!t.couplesJoints()) {
    j["body1"] = "a";
    j["body2"] = "b";
  }
  for (const TypeField& f : t.fields) {
    const std::string key(jointFieldName(f.field));
    switch (f.field) {
      case JointField::Anchor:
        j[key] = {0.5, 0, 0};
        break;
      case JointField::Anchor1:
        j[key] = {1, 0, 0};
        break;
      case JointField::Anchor2:
        j[key] = {0, 0, 0};
        break;
      case JointField::Axis:
        j[key] = {0, 0, 1};
        break;
      case JointField::Axis1:
        j[key] = {1, 0, 0};
        break;
      case JointField::Axis2:
        j[key] = {0, 1, 0};
        break;
      case JointField::Length:
        j[key] = 1.0;
        break;
      case JointField::Rope:
        j[key] = true;
        break;
      case JointField::Cone:
        j[key] = {{"swing1", 0.5}, {"swing2", 0.25}};
        break;
      case JointField::Ratio:
        j[key] = 2.0;
        break;
      case JointField::Axes:
        j[key] = json::parse(R"([{"type": "hinge", "axis": [0, 0, 1], "anchor": [0, 0, 0]}])");
        break;
      case JointField::Leader:
        j[key] = "h1";
        break;
      case JointField::Follower:
        j[key] = "h2";
        break;
      case JointField::Offset:
        j[key] = 0.1;
        break;
    }
  }
  scene["joints"].push_back(j);
  return scene;
}

// Each type's fields as the registry lists them (JointTypeInfo::fields): all of them read, each
// required one refused when missing, every other type's field refused as not this type's, and
// the joint written and read back to the same text.
TEST(Schema, EveryJointTypeTakesItsFieldsAndNoOthers) {
  for (const JointTypeInfo& t : jointTypes()) {
    SCOPED_TRACE(std::string(t.name));
    const json scene = jointScene(t);
    EXPECT_EQ(errorOf(scene), "accepted");
    const Scene parsed = parseScene(scene.dump(), "s.json");
    EXPECT_EQ(writeSceneJson(parseScene(writeSceneJson(parsed), "w.json")), writeSceneJson(parsed));
    for (const TypeField& f : t.fields) {
      if (!f.required) continue;
      json missing = scene;
      missing["joints"][2].erase(std::string(jointFieldName(f.field)));
      EXPECT_EQ(errorOf(missing),
                fmt::format("joints[2].{}: missing required field", jointFieldName(f.field)));
    }
    for (int k = 0; k <= static_cast<int>(JointField::Offset); ++k) {
      const auto field = static_cast<JointField>(k);
      if (t.uses(field)) continue;
      json other = scene;
      other["joints"][2][std::string(jointFieldName(field))] = 1.0;
      EXPECT_EQ(errorOf(other),
                fmt::format("joints[2].{}: not used by a {} joint", jointFieldName(field), t.name));
    }
  }
}

// A misspelt joint field is named with the closest of those its type takes.
TEST(Schema, MisspeltJointFieldsAreNamedWithTheClosest) {
  json scene = baseScene();
  scene["joints"][0]["axsi"] = {0, 0, 1};
  EXPECT_EQ(errorOf(scene), "joints[0].axsi: unknown field (did you mean 'axis'?)");
  json limits = baseScene();
  limits["joints"][0]["limit"] = {{"lower", 0}};
  EXPECT_EQ(errorOf(limits), "joints[0].limit: unknown field (did you mean 'limits'?)");
}

// docs/scene-format.md shows each record's table as the description makes it, between the
// markers <!-- schema: NAME --> and <!-- /schema --> (`linx schema NAME` prints it).
TEST(Schema, DocsShowTheTablesTheDescriptionMakes) {
  std::ifstream in(std::string(LINX_DOCS_DIR) + "/scene-format.md");
  ASSERT_TRUE(in) << LINX_DOCS_DIR;
  std::stringstream text;
  text << in.rdbuf();
  const std::string docs = text.str();
  for (const schema::Record& r : schema::records()) {
    const std::string begin = "<!-- schema: " + r.name + " -->\n";
    const auto at = docs.find(begin);
    ASSERT_NE(at, std::string::npos) << "no table for " << r.name;
    const auto end = docs.find("<!-- /schema -->", at);
    ASSERT_NE(end, std::string::npos) << r.name;
    EXPECT_EQ(docs.substr(at + begin.size(), end - at - begin.size()), schema::markdownTable(r))
        << "docs/scene-format.md's table of " << r.name
        << " differs from the schema: `linx schema --docs docs/scene-format.md` rewrites it";
  }
}

}  // namespace
}  // namespace linx
