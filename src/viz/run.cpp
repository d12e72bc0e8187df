// Reading a run's output folder back: scene.json (nlohmann-json) and the CSV files (RFC 4180
// records, numbers by std::from_chars). Frames are keyed by the `time` column: a new time starts a
// new frame, and every file must list the same times in the same order.
#include "viz/run.hpp"

#include "io/quoting.hpp"

#include <linx/bounds.hpp>
#include <linx/run_files.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>

namespace linx::viz {

namespace fs = std::filesystem;
using json = nlohmann::json;

RunError::RunError(const std::string& file, const std::string& field, const std::string& problem)
    : std::runtime_error(io::visible(fmt::format("{}: {}: {}", file, field, problem))) {}

namespace {

std::string readText(const fs::path& path, const char* hint = nullptr) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw RunError(path.string(), "file",
                   hint ? fmt::format("cannot be read ({})", hint) : std::string("cannot be read"));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// --- scene.json ------------------------------------------------------------------------------

class SceneJson {
 public:
  explicit SceneJson(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw RunError(file_, path, problem);
  }

  const json& at(const json& object, const std::string& path, const char* key) const {
    if (!object.is_object()) fail(path, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(path.empty() ? key : path + "." + key, "missing");
    return *it;
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number");
    const double x = j.get<double>();
    if (!std::isfinite(x)) fail(path, "must be finite");
    return x;
  }

  double positive(const json& j, const std::string& path, bool zero_ok = false) const {
    const double x = number(j, path);
    if (!(x > 0 || (zero_ok && x == 0))) fail(path, zero_ok ? "must be >= 0" : "must be > 0");
    return x;
  }

  // A length or a point of a shape: within the extent a scene may have (bounds.hpp), as the
  // scene reader holds them; a crafted scene.json beyond it would make no picture.
  double extent(const json& j, const std::string& path, bool zero_ok = false) const {
    const double x = positive(j, path, zero_ok);
    if (x > kMaxExtent) fail(path, fmt::format("must be at most {:g} m", kMaxExtent));
    return x;
  }

  Vec3 point(const json& j, const std::string& path) const {
    const Vec3 v = vec3(j, path);
    if (v.cwiseAbs().maxCoeff() > kMaxExtent)
      fail(path, fmt::format("must lie within {:g} m", kMaxExtent));
    return v;
  }

  Vec3 direction(const json& j, const std::string& path) const {
    const Vec3 v = vec3(j, path);
    if (!(v.norm() > 0)) fail(path, "must not be zero");
    return v.normalized();
  }

  Vec3 vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "expected [x, y, z]");
    return {number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]")};
  }

  Quat quat(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 4) fail(path, "expected [w, x, y, z]");
    Quat q(number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]"),
           number(j[3], path + "[3]"));
    if (!(q.norm() > 0)) fail(path, "must not be zero");
    return q.normalized();
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string");
    return j.get<std::string>();
  }

  ShapeDef shape(const json& j, const std::string& path) const {
    ShapeDef s;
    const std::string type = string(at(j, path, "type"), path + ".type");
    const auto field = [&](const char* key) { return path + "." + key; };
    if (type == "sphere") {
      s.type = ShapeType::Sphere;
      s.radius = extent(at(j, path, "radius"), field("radius"));
    } else if (type == "box") {
      s.type = ShapeType::Box;
      s.size = point(at(j, path, "size"), field("size"));
      if (!(s.size.minCoeff() > 0)) fail(field("size"), "every edge must be > 0");
    } else if (type == "ellipsoid") {
      s.type = ShapeType::Ellipsoid;
      s.radii = point(at(j, path, "radii"), field("radii"));
      if (!(s.radii.minCoeff() > 0)) fail(field("radii"), "every semi-axis must be > 0");
    } else if (type == "capsule" || type == "cylinder") {
      s.type = type == "capsule" ? ShapeType::Capsule : ShapeType::Cylinder;
      s.radius = extent(at(j, path, "radius"), field("radius"));
      s.length = extent(at(j, path, "length"), field("length"), s.type == ShapeType::Capsule);
    } else if (type == "plane") {
      s.type = ShapeType::Plane;
      s.normal = direction(at(j, path, "normal"), field("normal"));
      s.offset = number(at(j, path, "offset"), field("offset"));
    } else if (type == "convex" || type == "mesh") {
      s.type = type == "convex" ? ShapeType::Convex : ShapeType::Mesh;
      const json& vertices = at(j, path, "vertices");
      if (!vertices.is_array()) fail(field("vertices"), "expected an array");
      for (std::size_t i = 0; i < vertices.size(); ++i)
        s.points.push_back(point(vertices[i], fmt::format("{}[{}]", field("vertices"), i)));
      const json& triangles = at(j, path, "triangles");
      if (!triangles.is_array()) fail(field("triangles"), "expected an array");
      for (std::size_t i = 0; i < triangles.size(); ++i) {
        const json& t = triangles[i];
        const std::string tp = fmt::format("{}[{}]", field("triangles"), i);
        if (!t.is_array() || t.size() != 3) fail(tp, "expected [i, j, k]");
        std::array<int, 3> tri{};
        for (int k = 0; k < 3; ++k) {
          if (!t[k].is_number_integer() || t[k].get<long long>() < 0 ||
              t[k].get<long long>() >= static_cast<long long>(s.points.size()))
            fail(tp, fmt::format("vertex indices must be in [0, {})", s.points.size()));
          tri[k] = t[k].get<int>();
        }
        s.triangles.push_back(tri);
      }
    } else {
      fail(field("type"), fmt::format("unknown shape type '{}'", type));
    }
    s.position = point(at(j, path, "position"), field("position"));
    s.orientation = quat(at(j, path, "orientation"), field("orientation"));
    return s;
  }

  void read(const std::string& text, Run& run) const {
    json root;
    try {
      root = json::parse(text);
    } catch (const json::parse_error& e) {
      fail("", fmt::format("not valid JSON: {}", e.what()));
    }
    const auto format = root.is_object() ? root.find("format") : root.end();
    if (!root.is_object() || format == root.end() || *format != "linx-run")
      fail("format", "not a linx run's scene.json (expected \"format\": \"linx-run\")");
    if (root.find("version") == root.end() || root["version"] != 1)
      fail("version", "unsupported version (this linx reads version 1)");
    if (const auto source = root.find("source"); source != root.end())
      run.source = string(*source, "source");
    run.gravity = vec3(at(root, "", "gravity"), "gravity");
    run.timestep = positive(at(root, "", "timestep"), "timestep");
    const json& every = at(root, "", "every");
    if (!every.is_number_integer() || every.get<long long>() < 1 ||
        every.get<long long>() > std::numeric_limits<int>::max())
      fail("every", "expected an integer >= 1");
    run.every = every.get<int>();
    if (const auto v = root.find("view"); v != root.end()) {
      if (!v->is_object()) fail("view", "expected an object");
      SceneView view;
      if (v->contains("eye")) view.eye = vec3((*v)["eye"], "view.eye");
      if (v->contains("target")) view.target = vec3((*v)["target"], "view.target");
      if (view.eye && view.target && (*view.eye - *view.target).norm() == 0)
        fail("view.target", "must differ from eye");
      if (v->contains("up")) view.up = direction((*v)["up"], "view.up");
      if (v->contains("fov")) view.fov = number((*v)["fov"], "view.fov");
      if (!(view.fov > 0 && view.fov < 180)) fail("view.fov", "must be in (0, 180) degrees");
      run.view = view;
    }

    const json& bodies = at(root, "", "bodies");
    if (!bodies.is_array()) fail("bodies", "expected an array");
    std::map<std::string, int> index;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const std::string path = fmt::format("bodies[{}]", i);
      RunBody b;
      b.name = string(at(bodies[i], path, "name"), path + ".name");
      if (b.name == "world") fail(path + ".name", "'world' names the fixed world, not a body");
      const json& is_static = at(bodies[i], path, "static");
      if (!is_static.is_boolean()) fail(path + ".static", "expected true or false");
      b.is_static = is_static.get<bool>();
      b.mass = number(at(bodies[i], path, "mass"), path + ".mass");
      const json& shapes = at(bodies[i], path, "shapes");
      if (!shapes.is_array()) fail(path + ".shapes", "expected an array");
      for (std::size_t k = 0; k < shapes.size(); ++k)
        b.shapes.push_back(shape(shapes[k], fmt::format("{}.shapes[{}]", path, k)));
      if (!index.emplace(b.name, static_cast<int>(i)).second)
        fail(path + ".name", fmt::format("duplicate body name '{}'", b.name));
      run.bodies.push_back(std::move(b));
    }

    const json& joints = at(root, "", "joints");
    if (!joints.is_array()) fail("joints", "expected an array");
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const std::string path = fmt::format("joints[{}]", i);
      const json& j = joints[i];
      RunJoint joint;
      joint.name = string(at(j, path, "name"), path + ".name");
      joint.type = string(at(j, path, "type"), path + ".type");
      const auto body = [&](const char* key) {
        const std::string name = string(at(j, path, key), path + "." + key);
        if (name == "world") return -1;
        const auto it = index.find(name);
        if (it == index.end()) fail(path + "." + key, fmt::format("no body named '{}'", name));
        return it->second;
      };
      joint.body1 = body("body1");
      joint.body2 = body("body2");
      joint.anchor1 = vec3(at(j, path, "anchor1"), path + ".anchor1");
      joint.anchor2 = vec3(at(j, path, "anchor2"), path + ".anchor2");
      if (j.contains("axis1")) joint.axis1 = vec3(j["axis1"], path + ".axis1");
      if (j.contains("axis2")) joint.axis2 = vec3(j["axis2"], path + ".axis2");
      run.joints.push_back(std::move(joint));
    }
  }

 private:
  std::string file_;
};

// --- CSV -------------------------------------------------------------------------------------

// Splits RFC 4180 text into records of fields; each record remembers its first line number.
struct Record {
  int line = 0;
  std::vector<std::string> fields;
  std::size_t end = 0;  // the offset just past its line break
};

std::vector<Record> parseCsv(const std::string& text, const std::string& file) {
  std::vector<Record> records;
  Record current{1, {}};
  std::string field;
  bool quoted = false, field_started = false;
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        field += c;
      }
    } else if (c == '"' && field.empty() && !field_started) {
      quoted = true;
      field_started = true;
    } else if (c == ',') {
      current.fields.push_back(std::move(field));
      field.clear();
      field_started = false;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      current.fields.push_back(std::move(field));
      field.clear();
      field_started = false;
      current.end = i + 1;
      records.push_back(std::move(current));
      current = Record{++line, {}};
    } else {
      field += c;
      field_started = true;
    }
  }
  if (quoted) throw RunError(file, fmt::format("line {}", current.line), "unterminated quote");
  if (field_started || !current.fields.empty()) {
    current.fields.push_back(std::move(field));
    records.push_back(std::move(current));
  }
  return records;
}

// A CSV file's column names, from its header line.
std::vector<std::string> columns(const run_files::RunFile& file) {
  std::vector<std::string> names;
  std::string_view rest = file.header;
  for (std::size_t comma; (comma = rest.find(',')) != std::string_view::npos;
       rest.remove_prefix(comma + 1))
    names.emplace_back(rest.substr(0, comma));
  names.emplace_back(rest);
  return names;
}

class CsvFile {
 public:
  CsvFile(const fs::path& path, const std::vector<std::string>& header)
      : CsvFile(path, std::vector<std::vector<std::string>>{header}) {}
  // The first of `accepted` headers is the current one; the others, older files'.
  CsvFile(const fs::path& path, const std::vector<std::vector<std::string>>& accepted)
      : file_(path.string()), records_(parseCsv(completeLines(readText(path)), file_)) {
    const auto match = std::find_if(accepted.begin(), accepted.end(), [&](const auto& h) {
      return !records_.empty() && records_[0].fields == h;
    });
    if (match == accepted.end()) {
      std::string expected;
      for (const std::string& h : accepted.front()) expected += (expected.empty() ? "" : ",") + h;
      throw RunError(file_, "line 1", fmt::format("expected the header '{}'", expected));
    }
    const std::vector<std::string>& header = *match;
    for (std::size_t i = 1; i < records_.size(); ++i) {
      if (records_[i].fields.size() != header.size()) {
        throw RunError(
            file_, fmt::format("line {}", records_[i].line),
            fmt::format("expected {} fields, got {}", header.size(), records_[i].fields.size()));
      }
    }
  }

  std::size_t rows() const { return records_.size() - 1; }
  /// The size of the file up to the end of its first `n` rows (0: the header alone).
  std::uint64_t bytesTo(std::size_t n) const { return records_[n].end; }
  const std::vector<std::string>& row(std::size_t i) const { return records_[i + 1].fields; }

  [[noreturn]] void fail(std::size_t i, const std::string& problem) const {
    throw RunError(file_, fmt::format("line {}", records_[i + 1].line), problem);
  }

  // Field k of row i as a number; an empty field is NaN when `empty_ok`.
  double number(std::size_t i, std::size_t k, bool empty_ok = false) const {
    const std::string& f = row(i)[k];
    if (f.empty() && empty_ok) return std::numeric_limits<double>::quiet_NaN();
    double x = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), x);
    if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(x))
      fail(i, fmt::format("field {}: '{}' is not a finite number", k + 1, f));
    return x;
  }

  const std::string& file() const { return file_; }
  /// The file ended part-way through a line (a run killed while writing), which was left out.
  bool truncated() const { return truncated_; }

 private:
  // The text up to its last line break: every line a recorder writes ends with one.
  std::string completeLines(std::string text) {
    const std::size_t end = text.rfind('\n');
    const std::size_t keep = end == std::string::npos ? 0 : end + 1;
    truncated_ = keep < text.size();
    text.resize(keep);
    return text;
  }

  std::string file_;
  bool truncated_ = false;  // set while records_ is initialized: declared before it
  std::vector<Record> records_;
};

}  // namespace

Vec3 worldPoint(const Frame& frame, int body, const Vec3& local) {
  if (body < 0) return local;
  const Pose& p = frame.poses[static_cast<std::size_t>(body)];
  return p.position + p.orientation * local;
}

Run readRun(const fs::path& dir) {
  Run run;
  run.dir = dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw RunError(dir.string(), "folder", "not a directory");
  const fs::path scene_path = dir / run_files::kScene.name;
  const std::string scene_file = scene_path.string();
  try {
    SceneJson(scene_file)
        .read(readText(scene_path, "a run folder written by `linx run`; rerun the scene"), run);
  } catch (const json::exception& e) {  // a value of an unexpected type deep in the document
    throw RunError(scene_file, "document", e.what());
  }
  const std::size_t nb = run.bodies.size(), nj = run.joints.size();
  std::map<std::string, int> body_index;
  for (std::size_t i = 0; i < nb; ++i) body_index[run.bodies[i].name] = static_cast<int>(i);

  // The three tables of frames. A run killed while it wrote them ends part-way through a frame
  // (bodies.csv, joints.csv and world.csv are written in that order, a frame at a time): the
  // frames every file holds in full are read, and the rest is left out (Run::truncated).
  const CsvFile bodies(dir / run_files::kBodies.name, columns(run_files::kBodies));
  // With the joints' reactions (fx ... tz) and further coordinates, or without them as runs before
  // they were written.
  const CsvFile joints(dir / run_files::kJoints.name, {columns(run_files::kJoints),
                                                       {"time", "joint", "coordinate", "error",
                                                        "fx", "fy", "fz", "tx", "ty", "tz"},
                                                       {"time", "joint", "coordinate", "error"}});
  const CsvFile world(dir / run_files::kWorld.name, columns(run_files::kWorld));
  if (nb == 0) throw RunError(scene_file, "bodies", "no bodies");
  const std::size_t frames =
      std::min({bodies.rows() / nb, nj > 0 ? joints.rows() / nj : bodies.rows(), world.rows()});
  if (frames == 0) throw RunError(bodies.file(), "rows", "no complete frame");
  // One frame more in an earlier-written file, and part of one, is as far as a kill can leave
  // the files apart; anything else is a damaged folder.
  const auto check = [&](const CsvFile& file, std::size_t rows_per_frame, const char* what) {
    const std::size_t rows = file.rows();
    if (rows < frames * rows_per_frame || rows >= (frames + 2) * rows_per_frame)
      throw RunError(
          file.file(), "rows",
          fmt::format("{} rows is not {} frames of {} {}", rows, frames, rows_per_frame, what));
    run.truncated = run.truncated || rows > frames * rows_per_frame || file.truncated();
  };
  check(bodies, nb, nb == 1 ? "body" : "bodies");
  if (nj > 0) check(joints, nj, nj == 1 ? "joint" : "joints");
  check(world, 1, "row");
  run.whole_bytes[std::string(run_files::kBodies.name)] = bodies.bytesTo(frames * nb);
  if (nj > 0 || joints.rows() == 0)
    run.whole_bytes[std::string(run_files::kJoints.name)] = joints.bytesTo(frames * nj);
  run.whole_bytes[std::string(run_files::kWorld.name)] = world.bytesTo(frames);
  run.frames.resize(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    Frame& frame = run.frames[f];
    frame.poses.resize(nb);
    frame.linear_velocity.resize(nb);
    frame.angular_velocity.resize(nb);
    for (std::size_t b = 0; b < nb; ++b) {
      const std::size_t r = f * nb + b;
      const double t = bodies.number(r, 0);
      if (b == 0) {
        frame.time = t;
        if (f > 0 && !(t > run.frames[f - 1].time)) bodies.fail(r, "time does not increase");
      } else if (t != frame.time) {
        bodies.fail(r, fmt::format("expected time {} (a frame lists every body)", frame.time));
      }
      if (bodies.row(r)[1] != run.bodies[b].name)
        bodies.fail(r, fmt::format("expected body '{}' (scene.json's order)", run.bodies[b].name));
      double c[13];
      for (int k = 0; k < 13; ++k) c[k] = bodies.number(r, 2 + static_cast<std::size_t>(k));
      Quat q(c[3], c[4], c[5], c[6]);
      if (!(q.norm() > 0)) bodies.fail(r, "zero quaternion");
      frame.poses[b] = Pose{Vec3(c[0], c[1], c[2]), q.normalized()};
      frame.linear_velocity[b] = Vec3(c[7], c[8], c[9]);
      frame.angular_velocity[b] = Vec3(c[10], c[11], c[12]);
    }
  }

  // joints.csv: nj rows per frame.
  for (std::size_t f = 0; f < frames; ++f) {
    Frame& frame = run.frames[f];
    frame.joint_coordinate.resize(nj);
    frame.joint_error.resize(nj);
    for (std::size_t j = 0; j < nj; ++j) {
      const std::size_t r = f * nj + j;
      if (joints.number(r, 0) != frame.time)
        joints.fail(r, fmt::format("expected time {} (bodies.csv's frame)", frame.time));
      if (joints.row(r)[1] != run.joints[j].name)
        joints.fail(r, fmt::format("expected joint '{}'", run.joints[j].name));
      frame.joint_coordinate[j] = joints.number(r, 2, true);
      frame.joint_error[j] = joints.number(r, 3);
    }
  }

  // world.csv: one row per frame.
  for (std::size_t f = 0; f < frames; ++f) {
    Frame& frame = run.frames[f];
    if (world.number(f, 0) != frame.time)
      world.fail(f, fmt::format("expected time {} (bodies.csv's frame)", frame.time));
    frame.kinetic_energy = world.number(f, 1);
    frame.potential_energy = world.number(f, 2);
    const double iterations = world.number(f, 5);
    if (!(iterations >= 0 && iterations <= std::numeric_limits<int>::max() &&
          iterations == std::floor(iterations)))
      world.fail(f, fmt::format("field 6: '{}' is not an iteration count", world.row(f)[5]));
    frame.solver_iterations = static_cast<int>(iterations);
    frame.residual = world.number(f, 6);
  }

  // contacts.csv (optional): any number of rows per frame, frames in time order.
  const fs::path contacts_path = dir / run_files::kContacts.name;
  if (fs::exists(contacts_path, ec)) {
    run.has_contacts = true;
    const CsvFile contacts(contacts_path, columns(run_files::kContacts));
    run.truncated = run.truncated || contacts.truncated();
    std::size_t f = 0, read = 0;  // rows read: those of the frames read
    for (std::size_t r = 0; r < contacts.rows(); ++r) {
      const double t = contacts.number(r, 0);
      if (t > run.frames.back().time && run.truncated) break;  // a frame the others lack
      while (f < frames && run.frames[f].time < t) ++f;
      if (f == frames || run.frames[f].time != t)
        contacts.fail(r, fmt::format("time {} is not a frame of bodies.csv (or out of order)", t));
      RunContact c;
      for (int k = 0; k < 2; ++k) {
        const auto it = body_index.find(contacts.row(r)[1 + static_cast<std::size_t>(k)]);
        if (it == body_index.end())
          contacts.fail(r, fmt::format("no body named '{}'", contacts.row(r)[1 + k]));
        (k == 0 ? c.body1 : c.body2) = it->second;
      }
      c.point = Vec3(contacts.number(r, 3), contacts.number(r, 4), contacts.number(r, 5));
      c.normal = Vec3(contacts.number(r, 6), contacts.number(r, 7), contacts.number(r, 8));
      c.depth = contacts.number(r, 9);
      c.normal_impulse = contacts.number(r, 10);
      run.frames[f].contacts.push_back(c);
      read = r + 1;
    }
    run.whole_bytes[std::string(run_files::kContacts.name)] = contacts.bytesTo(read);
  }
  return run;
}

}  // namespace linx::viz
