// ParaView output (docs/visualization.md, "ParaView"): the shapes' surfaces checked against the
// analytic shapes posed from bodies.csv, point velocities against v + w x (p - c), joint arrays
// against joints.csv, and the .pvd's timesteps against the recorded times. The .vtp files are read
// back by a small parser of their own (base64 arrays), not by the writer's code.
#include "viz/run.hpp"
#include "viz/tessellate.hpp"
#include "viz/vtk.hpp"

#include <linx/linx.hpp>
#include <linx/recorder.hpp>
#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using linx::Quat;
using linx::Vec3;

namespace {

// --- reading the files back ------------------------------------------------------------------

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<unsigned char> decodeBase64(const std::string& text) {
  std::vector<unsigned char> out;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    if (c >= '0' && c <= '9') v = c - '0' + 52;
    if (c == '+') v = 62;
    if (c == '/') v = 63;
    if (v < 0) continue;  // whitespace and padding
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    if (++count == 4) {
      out.push_back(static_cast<unsigned char>(bits >> 16));
      out.push_back(static_cast<unsigned char>(bits >> 8));
      out.push_back(static_cast<unsigned char>(bits));
      bits = 0;
      count = 0;
    }
  }
  if (count == 3) {
    out.push_back(static_cast<unsigned char>(bits >> 10));
    out.push_back(static_cast<unsigned char>(bits >> 2));
  } else if (count == 2) {
    out.push_back(static_cast<unsigned char>(bits >> 4));
  }
  return out;
}

// The text between <TAG ...> and </TAG>.
std::string section(const std::string& xml, const std::string& tag) {
  const std::size_t open = xml.find("<" + tag);
  const std::size_t start = xml.find('>', open);
  const std::size_t end = xml.find("</" + tag + ">", start);
  if (open == std::string::npos || end == std::string::npos) {
    ADD_FAILURE() << "no <" << tag << ">";
    return {};
  }
  return xml.substr(start + 1, end - start - 1);
}

// The value of attribute `name` in the first element starting at `from`.
std::string attribute(const std::string& xml, const std::string& name, std::size_t from = 0) {
  const std::size_t tag_end = xml.find('>', from);
  const std::size_t at = xml.find(" " + name + "=\"", from);
  if (at == std::string::npos || at > tag_end) return {};
  const std::size_t start = at + name.size() + 3;
  return xml.substr(start, xml.find('"', start) - start);
}

// The binary DataArray called `name` in `xml` (the first one), as values of T.
template <class T>
std::vector<T> dataArray(const std::string& xml, const std::string& name, const char* type,
                         int components = 1) {
  const std::size_t at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no array " << name;
    return {};
  }
  const std::size_t open = xml.rfind("<DataArray", at);
  EXPECT_EQ(attribute(xml, "type", open), type) << name;
  EXPECT_EQ(attribute(xml, "format", open), "binary") << name;
  EXPECT_EQ(attribute(xml, "NumberOfComponents", open),
            components == 1 ? "" : std::to_string(components))
      << name;
  const std::size_t start = xml.find('>', at) + 1;
  const std::vector<unsigned char> raw =
      decodeBase64(xml.substr(start, xml.find("</DataArray>", start) - start));
  std::uint64_t bytes = 0;
  EXPECT_GE(raw.size(), sizeof bytes);
  std::memcpy(&bytes, raw.data(), sizeof bytes);
  EXPECT_EQ(raw.size(), sizeof bytes + bytes) << name;
  EXPECT_EQ(bytes % (sizeof(T) * static_cast<std::size_t>(components)), 0u) << name;
  std::vector<T> values(bytes / sizeof(T));
  // An empty array (a frame without contacts) has no data to copy: memcpy must not see its null.
  if (!values.empty())
    std::memcpy(values.data(), raw.data() + sizeof bytes, values.size() * sizeof(T));
  return values;
}

std::vector<Vec3> vectors(const std::vector<double>& xyz) {
  std::vector<Vec3> out;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    out.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  return out;
}

std::vector<std::vector<std::string>> csv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(path));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    std::string f;
    while (std::getline(s, f, ',')) fields.push_back(f);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    rows.push_back(fields);
  }
  return rows;
}

double number(const std::string& text) {
  return text.empty() ? std::nan("") : std::strtod(text.c_str(), nullptr);
}

// --- the run -----------------------------------------------------------------------------------

struct BodyState {
  Vec3 c, v, w;
  Quat q;
};

// Frames of bodies.csv: time and each body's state by name.
struct Truth {
  std::vector<double> times;
  std::vector<std::map<std::string, BodyState>> bodies;
};

Truth readTruth(const fs::path& dir) {
  Truth t;
  for (const auto& r : csv(dir / "bodies.csv")) {
    const double time = number(r[0]);
    if (t.times.empty() || time != t.times.back()) {
      t.times.push_back(time);
      t.bodies.emplace_back();
    }
    t.bodies.back()[r[1]] =
        BodyState{Vec3(number(r[2]), number(r[3]), number(r[4])),
                  Vec3(number(r[9]), number(r[10]), number(r[11])),
                  Vec3(number(r[12]), number(r[13]), number(r[14])),
                  Quat(number(r[5]), number(r[6]), number(r[7]), number(r[8])).normalized()};
  }
  return t;
}

constexpr double kBallR = 0.3, kPebbleR = 0.1, kGround = -5.0;
const Vec3 kCrate(0.4, 0.6, 0.8);
const std::vector<Vec3> kTag = {{0, 0, 0}, {0.2, 0, 0}, {0, 0.2, 0}, {0, 0, 0.2}};

// Body order: ball, crate, link, tag, ground, pebble.
constexpr const char* kScene = R"({
  "gravity": [0, 0, 0],
  "timestep": 0.002,
  "duration": 0.1,
  "bodies": [
    {"name": "ball", "mass": 1, "position": [0, 0, 1], "linear_velocity": [1, 0, 0],
     "angular_velocity": [0, 0, 5], "shapes": [{"type": "sphere", "radius": 0.3}]},
    {"name": "crate", "mass": 2, "position": [2, 0, 1],
     "orientation": [0.9238795325112867, 0.3826834323650898, 0, 0],
     "linear_velocity": [0, 0.5, 0], "angular_velocity": [1, 2, 3],
     "shapes": [{"type": "box", "size": [0.4, 0.6, 0.8]}]},
    {"name": "link", "mass": 1, "position": [0, 2, 1], "angular_velocity": [2, 0, 0],
     "shapes": [{"type": "cylinder", "radius": 0.05, "length": 0.5},
                {"type": "capsule", "radius": 0.04, "length": 0.2, "position": [0, 0, -0.3]}]},
    {"name": "tag", "mass": 1, "position": [-2, 0, 1],
     "shapes": [{"type": "convex", "points": [[0, 0, 0], [0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]]}]},
    {"name": "ground", "static": true,
     "shapes": [{"type": "plane", "normal": [0, 0, 1], "offset": -5}]},
    {"name": "pebble", "mass": 0.1, "position": [3, 3, -4.901], "linear_velocity": [0, 0, -1],
     "shapes": [{"type": "sphere", "radius": 0.1}]}
  ],
  "joints": [
    {"name": "pivot", "type": "hinge", "body1": "link", "anchor": [0, 2, 1.25], "axis": [1, 0, 0]},
    {"name": "weld", "type": "fixed", "body1": "tag"}
  ]
})";

// Simulates kScene for `steps` steps, recording every `every`, with contacts.
fs::path makeRun(const fs::path& dir, int steps = 50, int every = 10) {
  fs::remove_all(dir);
  const linx::Scene scene = linx::parseScene(kScene, "vtk-test.json");
  linx::World world = linx::buildWorld(scene);
  linx::Recorder recorder(dir, linx::RecorderOptions{.contacts = true});
  recorder.writeFile("scene.json", linx::runSceneJson(scene, world, every));
  recorder.record(world);
  for (int step = 1; step <= steps; ++step) {
    world.step();
    if (step % every == 0) recorder.record(world);
  }
  recorder.finish();
  return dir;
}

fs::path tempDir(const std::string& name) {
  return fs::temp_directory_path() / ("linx_test_vtk_" + std::to_string(getpid()) + "_" + name);
}

struct DataSet {
  double time;
  int part;
  std::string file;
};

std::vector<DataSet> readCollection(const fs::path& pvd) {
  const std::string xml = slurp(pvd);
  EXPECT_NE(xml.find("<VTKFile type=\"Collection\""), std::string::npos);
  std::vector<DataSet> out;
  for (std::size_t at = xml.find("<DataSet"); at != std::string::npos;
       at = xml.find("<DataSet", at + 1)) {
    out.push_back({std::strtod(attribute(xml, "timestep", at).c_str(), nullptr),
                   std::atoi(attribute(xml, "part", at).c_str()), attribute(xml, "file", at)});
  }
  return out;
}

// Signed volume enclosed by a surface (divergence theorem): right only for a closed surface whose
// triangles turn counter-clockwise seen from outside.
double volume(const linx::viz::Surface& s) {
  double v = 0;
  for (const auto& t : s.triangles)
    v += s.points[static_cast<std::size_t>(t[0])].dot(
        s.points[static_cast<std::size_t>(t[1])].cross(s.points[static_cast<std::size_t>(t[2])]));
  return v / 6;
}

// Every triangle's own normal agrees with the normals of its corners.
void expectOutward(const linx::viz::Surface& s, const char* what) {
  ASSERT_EQ(s.points.size(), s.normals.size()) << what;
  for (const Vec3& n : s.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-12) << what;
  for (const auto& t : s.triangles) {
    const Vec3 &a = s.points[static_cast<std::size_t>(t[0])],
               &b = s.points[static_cast<std::size_t>(t[1])],
               &c = s.points[static_cast<std::size_t>(t[2])];
    const Vec3 n = (b - a).cross(c - a);
    ASSERT_GT(n.norm(), 0) << what << ": degenerate triangle";
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(n.normalized().dot(s.normals[static_cast<std::size_t>(t[k])]), 0.5) << what;
  }
}

}  // namespace

// --- tessellation ------------------------------------------------------------------------------

TEST(Tessellate, ClosedOutwardSurfacesOfTheRightVolume) {
  using linx::ShapeDef;
  using linx::ShapeType;
  using linx::viz::tessellate;
  const double pi = std::numbers::pi;

  const ShapeDef sphere{.type = ShapeType::Sphere, .radius = 0.7};
  const auto s2 = tessellate(sphere);
  EXPECT_EQ(s2.triangles.size(), 320u);
  for (const Vec3& p : s2.points) EXPECT_NEAR(p.norm(), 0.7, 1e-12);
  expectOutward(s2, "sphere");
  const double ball = 4.0 / 3 * pi * std::pow(0.7, 3);
  EXPECT_NEAR(volume(s2) / ball, 1.0, 0.05);
  const auto s4 = tessellate(sphere, {.sphere_subdivisions = 4});
  EXPECT_NEAR(volume(s4) / ball, 1.0, 0.005);

  const ShapeDef box{.type = ShapeType::Box, .size = Vec3(1, 2, 3)};
  const auto b = tessellate(box);
  expectOutward(b, "box");
  EXPECT_NEAR(volume(b), 6.0, 1e-12);
  for (const Vec3& p : b.points)
    EXPECT_NEAR(p.cwiseAbs().cwiseQuotient(Vec3(0.5, 1, 1.5)).maxCoeff(), 1.0, 1e-12);

  const ShapeDef cylinder{.type = ShapeType::Cylinder, .radius = 0.5, .length = 2};
  const auto c = tessellate(cylinder, {.segments = 64});
  expectOutward(c, "cylinder");
  // A regular 64-gon prism: (n/2) r^2 sin(2 pi / n) L exactly.
  EXPECT_NEAR(volume(c), 32 * 0.25 * std::sin(2 * pi / 64) * 2, 1e-12);
  for (const Vec3& p : c.points) {
    EXPECT_LE(std::hypot(p.x(), p.y()), 0.5 + 1e-12);
    EXPECT_LE(std::abs(p.z()), 1.0 + 1e-12);
  }

  const ShapeDef capsule{.type = ShapeType::Capsule, .radius = 0.5, .length = 1};
  const auto k = tessellate(capsule, {.segments = 64});
  expectOutward(k, "capsule");
  const double pill = pi * 0.25 * 1 + 4.0 / 3 * pi * 0.125;
  EXPECT_NEAR(volume(k) / pill, 1.0, 0.01);
  for (const Vec3& p : k.points) {  // on the surface: r from the segment between the cap centres
    const double z = std::clamp(p.z(), -0.5, 0.5);
    EXPECT_NEAR((p - Vec3(0, 0, z)).norm(), 0.5, 1e-12);
  }

  // A tetrahedron whose triangles are given inward: turned outward.
  ShapeDef tet{.type = ShapeType::Convex};
  tet.points = kTag;
  tet.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // outward
  EXPECT_NEAR(volume(tessellate(tet)), 0.008 / 6, 1e-15);
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // inward
  EXPECT_NEAR(volume(tessellate(tet)), 0.008 / 6, 1e-15);
  expectOutward(tessellate(tet), "convex");

  // A plane: a square of the asked size around the point of the plane nearest to the centre.
  const ShapeDef plane{.type = ShapeType::Plane, .normal = Vec3(0, 1, 0), .offset = 2};
  const auto p = tessellate(plane, {.plane_half_size = 3, .plane_center = Vec3(1, 7, 1)});
  ASSERT_EQ(p.triangles.size(), 2u);
  expectOutward(p, "plane");
  for (const Vec3& q : p.points) {
    EXPECT_NEAR(q.y(), 2, 1e-12);
    EXPECT_NEAR(std::abs(q.x() - 1), 3, 1e-12);
    EXPECT_NEAR(std::abs(q.z() - 1), 3, 1e-12);
  }
}

// --- the files of a run ------------------------------------------------------------------------

TEST(Vtk, FramesMatchTheRecordedRun) {
  const fs::path dir = makeRun(tempDir("run"));
  const linx::viz::VtkSummary summary = linx::viz::writeVtk(linx::viz::readRun(dir), dir);
  const Truth truth = readTruth(dir);
  ASSERT_EQ(truth.times.size(), 6u);
  EXPECT_EQ(summary.frames, 6);
  EXPECT_EQ(summary.collection, dir / "run.pvd");
  EXPECT_EQ(summary.folder, dir / "vtk");

  // The collection: each frame's bodies, joints and contacts at the frame's time, in order.
  const std::vector<DataSet> sets = readCollection(dir / "run.pvd");
  ASSERT_EQ(sets.size(), 3 * truth.times.size());
  for (std::size_t f = 0; f < truth.times.size(); ++f) {
    const char* parts[] = {"bodies", "joints", "contacts"};
    for (int part = 0; part < 3; ++part) {
      const DataSet& s = sets[3 * f + static_cast<std::size_t>(part)];
      EXPECT_EQ(s.time, truth.times[f]);
      EXPECT_EQ(s.part, part);
      char name[64];
      std::snprintf(name, sizeof name, "vtk/%s_%06zu.vtp", parts[part], f);
      EXPECT_EQ(s.file, name);
      EXPECT_TRUE(fs::is_regular_file(dir / s.file)) << s.file;
    }
  }
  for (const auto& entry : fs::directory_iterator(dir / "vtk"))
    EXPECT_EQ(entry.path().extension(), ".vtp") << entry.path() << ": left over";

  const std::vector<std::string> names = {"ball", "crate", "link", "tag", "ground", "pebble"};
  const auto joints = csv(dir / "joints.csv");
  const auto contacts = csv(dir / "contacts.csv");
  std::size_t contact_row = 0;
  for (std::size_t f = 0; f < truth.times.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const auto& state = truth.bodies[f];

    // Bodies: every triangle's points on its own body's shape, posed from bodies.csv.
    const std::string xml = slurp(dir / sets[3 * f].file);
    EXPECT_EQ(dataArray<double>(section(xml, "FieldData"), "TimeValue", "Float64"),
              std::vector<double>{truth.times[f]});
    EXPECT_EQ(attribute(xml, "NumberOfTuples", xml.find("Name=\"TimeValue\"")), "1");
    const std::string polys = section(xml, "Polys");
    const auto points = vectors(dataArray<double>(section(xml, "Points"), "Points", "Float64", 3));
    const auto velocity =
        vectors(dataArray<double>(section(xml, "PointData"), "velocity", "Float64", 3));
    const auto normals = dataArray<float>(section(xml, "PointData"), "Normals", "Float32", 3);
    const auto body_id = dataArray<std::int32_t>(section(xml, "CellData"), "body_id", "Int32");
    const auto shape_id = dataArray<std::int32_t>(section(xml, "CellData"), "shape_id", "Int32");
    const auto connectivity = dataArray<std::int32_t>(polys, "connectivity", "Int32");
    const auto offsets = dataArray<std::int32_t>(polys, "offsets", "Int32");
    ASSERT_EQ(velocity.size(), points.size());
    ASSERT_EQ(normals.size(), 3 * points.size());
    ASSERT_EQ(body_id.size(), offsets.size());
    ASSERT_EQ(shape_id.size(), offsets.size());
    ASSERT_EQ(connectivity.size(), 3 * offsets.size());
    EXPECT_EQ(attribute(xml, "NumberOfPoints", xml.find("<Piece")), std::to_string(points.size()));
    EXPECT_EQ(attribute(xml, "NumberOfPolys", xml.find("<Piece")), std::to_string(offsets.size()));

    std::map<int, int> cells;  // per body
    std::vector<int> point_body(points.size(), -1);
    std::vector<bool> corner_seen(8, false);
    for (std::size_t c = 0; c < offsets.size(); ++c) {
      EXPECT_EQ(offsets[c], static_cast<std::int32_t>(3 * (c + 1)));
      const int b = body_id[c];
      ASSERT_TRUE(b >= 0 && b < 6);
      ++cells[b];
      const BodyState& s = state.at(names[static_cast<std::size_t>(b)]);
      const linx::Mat3 r = s.q.toRotationMatrix();
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<std::size_t>(connectivity[3 * c + static_cast<std::size_t>(k)]);
        ASSERT_LT(i, points.size());
        EXPECT_TRUE(point_body[i] == -1 || point_body[i] == b) << "point shared by two bodies";
        point_body[i] = b;
        const Vec3& p = points[i];
        const Vec3 local = r.transpose() * (p - s.c);
        switch (b) {
          case 0:  // ball
            EXPECT_NEAR((p - s.c).norm(), kBallR, 1e-9);
            EXPECT_EQ(shape_id[c], 0);
            break;
          case 1: {  // crate: on the box's faces, and its corners are there
            const Vec3 h = kCrate / 2;
            EXPECT_NEAR(local.cwiseAbs().cwiseQuotient(h).maxCoeff(), 1.0, 1e-9);
            for (int corner = 0; corner < 8; ++corner) {
              const Vec3 at((corner & 1 ? 1 : -1) * h.x(), (corner & 2 ? 1 : -1) * h.y(),
                            (corner & 4 ? 1 : -1) * h.z());
              if ((local - at).norm() < 1e-9) corner_seen[static_cast<std::size_t>(corner)] = true;
            }
            break;
          }
          case 2:  // link: a cylinder (radius 0.05, length 0.5) and a capsule below it
            if (shape_id[c] == 0) {
              EXPECT_LE(std::hypot(local.x(), local.y()), 0.05 + 1e-9);
              EXPECT_LE(std::abs(local.z()), 0.25 + 1e-9);
            } else {
              EXPECT_EQ(shape_id[c], 1);
              const double z = std::clamp(local.z(), -0.4, -0.2);
              EXPECT_NEAR((local - Vec3(0, 0, z)).norm(), 0.04, 1e-9);
            }
            break;
          case 3: {  // tag: its points are the tetrahedron's vertices
            double nearest = 1e9;
            for (const Vec3& v : kTag) nearest = std::min(nearest, (local - v).norm());
            EXPECT_LT(nearest, 1e-9);
            break;
          }
          case 4:  // ground: on the plane z = -5
            EXPECT_NEAR(p.z(), kGround, 1e-12);
            break;
          case 5:
            EXPECT_NEAR((p - s.c).norm(), kPebbleR, 1e-9);
            break;
        }
      }
    }
    for (int corner = 0; corner < 8; ++corner)
      EXPECT_TRUE(corner_seen[static_cast<std::size_t>(corner)]) << "crate corner " << corner;
    EXPECT_EQ(cells[0], 320);
    EXPECT_EQ(cells[1], 12);
    EXPECT_EQ(cells[3], 4);
    EXPECT_EQ(cells[4], 2);
    EXPECT_EQ(cells[5], 320);

    // Rigid-body velocity of every point, from bodies.csv.
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_GE(point_body[i], 0) << "point " << i << " in no triangle";
      const BodyState& s = state.at(names[static_cast<std::size_t>(point_body[i])]);
      const Vec3 expected = s.v + s.w.cross(points[i] - s.c);
      EXPECT_LT((velocity[i] - expected).norm(), 1e-9 * (1 + expected.norm()));
    }
    // The ball spins at 5 rad/s about z: its equator moves 1.5 m/s relative to its centre.
    if (f == 0) {
      double fastest = 0;
      for (std::size_t i = 0; i < points.size(); ++i)
        if (point_body[i] == 0)
          fastest = std::max(fastest, (velocity[i] - state.at("ball").v).norm());
      EXPECT_NEAR(fastest, 5 * kBallR, 1e-9);
    }

    // Joints: one vertex per joint at its anchor on body1, with joints.csv's values.
    const std::string jxml = slurp(dir / sets[3 * f + 1].file);
    const auto anchors =
        vectors(dataArray<double>(section(jxml, "Points"), "Points", "Float64", 3));
    const auto error = dataArray<double>(jxml, "joint_error", "Float64");
    const auto coordinate = dataArray<double>(jxml, "joint_coordinate", "Float64");
    const auto joint_id = dataArray<std::int32_t>(jxml, "joint_id", "Int32");
    const auto axis = vectors(dataArray<double>(jxml, "axis", "Float64", 3));
    ASSERT_EQ(anchors.size(), 2u);
    ASSERT_EQ(error.size(), 2u);
    ASSERT_EQ(coordinate.size(), 2u);
    ASSERT_EQ(axis.size(), 2u);
    EXPECT_EQ(joint_id, (std::vector<std::int32_t>{0, 1}));
    EXPECT_EQ(dataArray<std::int32_t>(section(jxml, "Verts"), "connectivity", "Int32"),
              (std::vector<std::int32_t>{0, 1}));
    EXPECT_EQ(dataArray<std::int32_t>(section(jxml, "Verts"), "offsets", "Int32"),
              (std::vector<std::int32_t>{1, 2}));
    for (std::size_t j = 0; j < 2; ++j) {
      const auto& row = joints[2 * f + j];
      ASSERT_EQ(number(row[0]), truth.times[f]);
      EXPECT_EQ(error[j], number(row[3]));
      if (row[2].empty()) {
        EXPECT_TRUE(std::isnan(coordinate[j]));
      } else {
        EXPECT_EQ(coordinate[j], number(row[2]));
      }
    }
    EXPECT_EQ(joints[2 * f][1], "pivot");
    EXPECT_TRUE(std::isnan(coordinate[1]));  // a fixed joint has no coordinate
    // pivot: 0.25 m above the link's centre in its frame, axis x of the link's frame.
    const BodyState& link = state.at("link");
    EXPECT_LT((anchors[0] - (link.c + link.q * Vec3(0, 0, 0.25))).norm(), 1e-12);
    EXPECT_LT((axis[0] - link.q * Vec3::UnitX()).norm(), 1e-12);
    EXPECT_LT((anchors[1] - state.at("tag").c).norm(), 1e-12);  // default anchor: body1's centre
    EXPECT_EQ(axis[1], Vec3::Zero());

    // Contacts: contacts.csv's rows of this frame.
    const std::string cxml = slurp(dir / sets[3 * f + 2].file);
    const auto cpoints =
        vectors(dataArray<double>(section(cxml, "Points"), "Points", "Float64", 3));
    const auto impulse = dataArray<double>(cxml, "normal_impulse", "Float64");
    const auto cnormal = vectors(dataArray<double>(cxml, "normal", "Float64", 3));
    ASSERT_EQ(impulse.size(), cpoints.size());
    ASSERT_EQ(cnormal.size(), cpoints.size());
    for (std::size_t i = 0; i < cpoints.size(); ++i, ++contact_row) {
      ASSERT_LT(contact_row, contacts.size());
      const auto& row = contacts[contact_row];
      EXPECT_EQ(number(row[0]), truth.times[f]);
      EXPECT_EQ(cpoints[i], Vec3(number(row[3]), number(row[4]), number(row[5])));
      EXPECT_EQ(cnormal[i], Vec3(number(row[6]), number(row[7]), number(row[8])));
      EXPECT_EQ(impulse[i], number(row[10]));
    }
  }
  EXPECT_EQ(contact_row, contacts.size());
  EXPECT_GT(contacts.size(), 0u) << "the pebble is thrown at the ground";
  fs::remove_all(dir);
}

TEST(Vtk, RewritingRemovesFramesOfAnEarlierExport) {
  const fs::path dir = makeRun(tempDir("rewrite"), 20, 10);
  fs::create_directories(dir / "vtk");
  std::ofstream(dir / "vtk" / "bodies_000007.vtp") << "old";
  std::ofstream(dir / "vtk" / "notes.txt") << "mine";
  EXPECT_EQ(linx::viz::writeVtk(linx::viz::readRun(dir), dir).frames, 3);
  EXPECT_FALSE(fs::exists(dir / "vtk" / "bodies_000007.vtp"));
  EXPECT_TRUE(fs::exists(dir / "vtk" / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir / "vtk" / "bodies_000002.vtp"));
  EXPECT_EQ(readCollection(dir / "run.pvd").size(), 9u);
  fs::remove_all(dir);
}

TEST(Vtk, FailuresLeaveNoFinalFiles) {
  const fs::path dir = makeRun(tempDir("fail"));
  const linx::viz::Run run = linx::viz::readRun(dir);

  // The folder cannot be made: a file is in the way.
  std::ofstream(dir / "vtk") << "in the way";
  try {
    linx::viz::writeVtk(run, dir);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "vtk").string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "run.pvd"));
  fs::remove(dir / "vtk");

  // A frame cannot be written (a folder holds its temporary name): the frames before it are not
  // left behind under their final names, nor under their temporary ones.
  fs::create_directories(dir / "vtk" / "bodies_000003.vtp.tmp");
  try {
    linx::viz::writeVtk(run, dir);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bodies_000003.vtp.tmp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot be written"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "run.pvd"));
  EXPECT_FALSE(fs::exists(dir / "run.pvd.tmp"));
  EXPECT_TRUE(fs::is_directory(dir / "vtk" / "bodies_000003.vtp.tmp")) << "not ours to remove";
  for (const auto& entry : fs::directory_iterator(dir / "vtk"))
    EXPECT_EQ(entry.path().filename(), "bodies_000003.vtp.tmp") << "left behind";
  fs::remove_all(dir / "vtk");

  // A read-only folder (meaningless for root, who may write anyway).
  if (geteuid() != 0) {
    fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(linx::viz::writeVtk(run, dir), std::runtime_error);
    fs::permissions(dir, fs::perms::owner_all);
    EXPECT_FALSE(fs::exists(dir / "run.pvd"));
  }
  fs::remove_all(dir);
}

// --- the command line ----------------------------------------------------------------------------

TEST(Vtk, CommandLine) {
  if (!fs::exists(LINX_CLI)) GTEST_SKIP() << LINX_CLI << " is not built";
  const fs::path dir = tempDir("cli");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene.in.json") << kScene;
  const fs::path out = dir / "out";
  const std::string run = std::string("'") + LINX_CLI + "' run '" +
                          (dir / "scene.in.json").string() + "' --out '" + out.string() +
                          "' --every 25 --vtk > '" + (dir / "log").string() + "' 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << slurp(dir / "log");
  EXPECT_NE(slurp(dir / "log")
                .find("wrote " + (out / "run.pvd").string() + " (3 frames in " +
                      (out / "vtk").string() + ")"),
            std::string::npos)
      << slurp(dir / "log");
  const auto sets = readCollection(out / "run.pvd");
  ASSERT_EQ(sets.size(), 6u);  // bodies and joints
  EXPECT_EQ(sets.back().time, readTruth(out).times.back());

  fs::remove_all(out / "vtk");
  fs::remove(out / "run.pvd");
  const std::string vtk = std::string("'") + LINX_CLI + "' vtk '" + out.string() + "' > '" +
                          (dir / "log").string() + "' 2>&1";
  ASSERT_EQ(std::system(vtk.c_str()), 0) << slurp(dir / "log");
  EXPECT_EQ(readCollection(out / "run.pvd").size(), 6u);
  fs::remove_all(dir);
}
