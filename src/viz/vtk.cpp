// VTK XML PolyData (.vtp) per frame and a ParaView collection (.pvd), written directly: the
// format is small enough that no VTK library is needed. Arrays are inline base64 "binary" data
// arrays: an unsigned 64-bit byte count followed by the values, encoded together.
#include "viz/vtk.hpp"

#include "viz/camera.hpp"
#include "viz/tessellate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace linx::viz {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw std::runtime_error(fmt::format("{}: {}", path.string(), reason));
}

// --- base64 arrays -----------------------------------------------------------------------------

void appendBase64(std::string& out, const unsigned char* data, std::size_t size) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  out.reserve(out.size() + (size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const std::uint32_t v = (std::uint32_t{data[i]} << 16) | (std::uint32_t{data[i + 1]} << 8) |
                            std::uint32_t{data[i + 2]};
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (i < size) {
    const bool two = i + 1 < size;
    const std::uint32_t v =
        (std::uint32_t{data[i]} << 16) | (two ? std::uint32_t{data[i + 1]} << 8 : 0u);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += two ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
}

template <class T>
constexpr const char* vtkType() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, float>) return "Float32";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
}

// One <DataArray> of `values` (components per tuple), on its own lines. Field data arrays state
// their number of tuples (readers take the others' from the piece).
template <class T>
void writeArray(std::ostream& out, const char* indent, const char* name, int components,
                const std::vector<T>& values, bool field = false) {
  out << indent << "<DataArray type=\"" << vtkType<T>() << '"';
  if (name) out << " Name=\"" << name << '"';
  if (components > 1) out << " NumberOfComponents=\"" << components << '"';
  if (field)
    out << " NumberOfTuples=\"" << values.size() / static_cast<std::size_t>(components) << '"';
  out << " format=\"binary\">\n";
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::vector<unsigned char> raw(sizeof bytes + bytes);
  std::memcpy(raw.data(), &bytes, sizeof bytes);
  if (bytes) std::memcpy(raw.data() + sizeof bytes, values.data(), bytes);
  std::string text(indent);
  text += "  ";
  appendBase64(text, raw.data(), raw.size());
  out << text << '\n' << indent << "</DataArray>\n";
}

void append(std::vector<double>& out, const Vec3& v) {
  out.insert(out.end(), {v.x(), v.y(), v.z()});
}

// --- one PolyData file -----------------------------------------------------------------------

// The arrays of one .vtp file: points with point data, and cells (vertices or triangles) with cell
// data.
struct PolyData {
  std::vector<double> points{};  // x y z per point
  std::vector<std::int32_t> connectivity{}, offsets{};
  bool triangles = false;  // Polys, else Verts
  struct Doubles {
    const char* name;
    int components;
    std::vector<double> values;
  };
  struct Ints {
    const char* name;
    std::vector<std::int32_t> values;
  };
  std::vector<Doubles> point_doubles{};
  std::vector<Ints> point_ints{}, cell_ints{};
  std::vector<float> normals{};  // empty, or x y z per point

  void clear() {
    points.clear();
    connectivity.clear();
    offsets.clear();
    normals.clear();
    for (auto& a : point_doubles) a.values.clear();
    for (auto& a : point_ints) a.values.clear();
    for (auto& a : cell_ints) a.values.clear();
  }

  void write(std::ostream& out, double time) const {
    const std::size_t n = points.size() / 3, cells = offsets.size();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\""
        << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
        << "\" header_type=\"UInt64\">\n  <PolyData>\n    <FieldData>\n";
    writeArray(out, "      ", "TimeValue", 1, std::vector<double>{time}, true);
    out << "    </FieldData>\n";
    out << fmt::format(
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"0\" "
        "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
        n, triangles ? 0 : cells, triangles ? cells : 0);
    out << "      <PointData" << (normals.empty() ? "" : " Normals=\"Normals\"") << ">\n";
    for (const auto& a : point_doubles) writeArray(out, "        ", a.name, a.components, a.values);
    for (const auto& a : point_ints) writeArray(out, "        ", a.name, 1, a.values);
    if (!normals.empty()) writeArray(out, "        ", "Normals", 3, normals);
    out << "      </PointData>\n      <CellData>\n";
    for (const auto& a : cell_ints) writeArray(out, "        ", a.name, 1, a.values);
    out << "      </CellData>\n      <Points>\n";
    writeArray(out, "        ", "Points", 3, points);
    out << "      </Points>\n";
    for (const char* kind : {"Verts", "Polys"}) {
      const bool these = (std::strcmp(kind, "Polys") == 0) == triangles;
      out << "      <" << kind << ">\n";
      writeArray(out, "        ", "connectivity", 1,
                 these ? connectivity : std::vector<std::int32_t>{});
      writeArray(out, "        ", "offsets", 1, these ? offsets : std::vector<std::int32_t>{});
      out << "      </" << kind << ">\n";
    }
    out << "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  }
};

// --- files under temporary names -------------------------------------------------------------

// Files written as NAME.tmp and renamed to NAME by commit(); the temporary files are removed if
// commit() is never reached.
class TempFiles {
 public:
  TempFiles() = default;
  TempFiles(const TempFiles&) = delete;
  TempFiles& operator=(const TempFiles&) = delete;
  ~TempFiles() {
    for (const auto& [temp, final_path] : files_) {
      std::error_code ec;
      fs::remove(temp, ec);
    }
  }

  // Opens FINAL.tmp for writing.
  std::ofstream open(const fs::path& final_path) {
    fs::path temp = final_path;
    temp += ".tmp";
    errno = 0;
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) {
      fail(temp, fmt::format("cannot be written ({})",
                             errno ? std::strerror(errno) : "cannot open the file"));
    }
    files_.emplace_back(temp, final_path);  // only files made here are removed
    return out;
  }

  // Closes `out` (opened as `final_path`), checking that everything reached the file.
  static void close(std::ofstream& out, const fs::path& final_path) {
    out.close();
    if (!out) fail(fs::path(final_path) += ".tmp", "cannot be written (write error: disk full?)");
  }

  // Renames every file to its final name: in the order opened, except that the first file opened
  // is renamed last (the collection, which must not name files that are not there yet).
  void commit() {
    for (std::size_t i = 1; i <= files_.size(); ++i) {
      const auto& [temp, final_path] = files_[i % files_.size()];
      std::error_code ec;
      fs::rename(temp, final_path, ec);
      if (ec) fail(final_path, fmt::format("cannot be written ({})", ec.message()));
    }
    files_.clear();
  }

 private:
  std::vector<std::pair<fs::path, fs::path>> files_;
};

// Shapes in their body frames, triangulated once.
struct BodySurface {
  std::vector<Vec3> points, normals;  // body frame
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::int32_t> shape;  // per triangle
};

std::vector<BodySurface> bodySurfaces(const Run& run, const VtkOptions& options) {
  TessellationOptions t;
  t.sphere_subdivisions = options.sphere_subdivisions;
  t.segments = options.segments;
  bool planes = false;
  for (const RunBody& b : run.bodies)
    for (const ShapeDef& s : b.shapes) planes = planes || s.type == ShapeType::Plane;
  Bounds bounds;
  if (planes && !run.frames.empty()) bounds = runBounds(run);
  std::vector<BodySurface> out(run.bodies.size());
  for (std::size_t i = 0; i < run.bodies.size(); ++i) {
    const Pose first =
        run.frames.empty() ? Pose{Vec3::Zero(), Quat::Identity()} : run.frames.front().poses[i];
    for (std::size_t k = 0; k < run.bodies[i].shapes.size(); ++k) {
      const ShapeDef& shape = run.bodies[i].shapes[k];
      if (shape.type == ShapeType::Plane) {
        // A square around the bounds' centre, 1.5 times the bounds' radius (at least 0.5 m) each
        // way. Planes only belong to static bodies, so the first frame's pose is every frame's.
        const Vec3 body = first.orientation.conjugate() * (bounds.center() - first.position);
        t.plane_center = shape.orientation.conjugate() * (body - shape.position);
        t.plane_half_size = std::max(1.5 * bounds.radius(), 0.5);
      }
      const Surface s = tessellate(shape, t);
      BodySurface& b = out[i];
      const int base = static_cast<int>(b.points.size());
      for (std::size_t p = 0; p < s.points.size(); ++p) {
        b.points.push_back(shape.position + shape.orientation * s.points[p]);
        b.normals.push_back(shape.orientation * s.normals[p]);
      }
      for (const auto& tri : s.triangles) {
        b.triangles.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
        b.shape.push_back(static_cast<std::int32_t>(k));
      }
    }
  }
  return out;
}

void fillBodies(PolyData& d, const Run& run, const Frame& frame,
                const std::vector<BodySurface>& surfaces) {
  d.clear();
  auto& velocity = d.point_doubles[0].values;
  auto& body_id = d.cell_ints[0].values;
  auto& shape_id = d.cell_ints[1].values;
  for (std::size_t i = 0; i < run.bodies.size(); ++i) {
    const BodySurface& s = surfaces[i];
    const Pose& pose = frame.poses[i];
    const Vec3& v = frame.linear_velocity[i];
    const Vec3& w = frame.angular_velocity[i];
    const auto base = static_cast<std::int32_t>(d.points.size() / 3);
    for (std::size_t p = 0; p < s.points.size(); ++p) {
      const Vec3 world = pose.position + pose.orientation * s.points[p];
      append(d.points, world);
      append(velocity, v + w.cross(world - pose.position));
      const Vec3 n = pose.orientation * s.normals[p];
      d.normals.insert(d.normals.end(), {static_cast<float>(n.x()), static_cast<float>(n.y()),
                                         static_cast<float>(n.z())});
    }
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      for (int c : s.triangles[t]) d.connectivity.push_back(base + c);
      d.offsets.push_back(static_cast<std::int32_t>(d.connectivity.size()));
      body_id.push_back(static_cast<std::int32_t>(i));
      shape_id.push_back(s.shape[t]);
    }
  }
}

void addVertex(PolyData& d, const Vec3& p) {
  append(d.points, p);
  d.connectivity.push_back(static_cast<std::int32_t>(d.offsets.size()));
  d.offsets.push_back(static_cast<std::int32_t>(d.connectivity.size()));
}

void fillJoints(PolyData& d, const Run& run, const Frame& frame) {
  d.clear();
  for (std::size_t j = 0; j < run.joints.size(); ++j) {
    const RunJoint& joint = run.joints[j];
    addVertex(d, worldPoint(frame, joint.body1, joint.anchor1));
    d.point_ints[0].values.push_back(static_cast<std::int32_t>(j));
    d.point_doubles[0].values.push_back(frame.joint_error[j]);
    d.point_doubles[1].values.push_back(frame.joint_coordinate[j]);
    Vec3 axis = Vec3::Zero();
    if (joint.axis1) {
      axis = joint.body1 < 0
                 ? *joint.axis1
                 : frame.poses[static_cast<std::size_t>(joint.body1)].orientation * *joint.axis1;
    }
    append(d.point_doubles[2].values, axis);
    d.point_ints[1].values.push_back(joint.body1);
    d.point_ints[2].values.push_back(joint.body2);
  }
}

void fillContacts(PolyData& d, const Frame& frame) {
  d.clear();
  for (const RunContact& c : frame.contacts) {
    addVertex(d, c.point);
    append(d.point_doubles[0].values, c.normal);
    d.point_doubles[1].values.push_back(c.depth);
    d.point_doubles[2].values.push_back(c.normal_impulse);
    d.point_ints[0].values.push_back(c.body1);
    d.point_ints[1].values.push_back(c.body2);
  }
}

// File names of earlier exports: PART_DIGITS.vtp for the parts written here.
bool ownFileName(const std::string& name) {
  for (const char* part : {"bodies_", "joints_", "contacts_"}) {
    const std::size_t n = std::strlen(part);
    if (name.size() > n + 4 && name.compare(0, n, part) == 0 &&
        name.compare(name.size() - 4, 4, ".vtp") == 0 &&
        std::all_of(name.begin() + static_cast<std::ptrdiff_t>(n), name.end() - 4,
                    [](char c) { return c >= '0' && c <= '9'; }))
      return true;
  }
  return false;
}

}  // namespace

VtkSummary writeVtk(const Run& run, const fs::path& dir, const VtkOptions& options) {
  VtkSummary summary;
  summary.folder = dir / "vtk";
  summary.collection = dir / "run.pvd";
  {
    std::error_code ec;
    fs::create_directories(summary.folder, ec);
    if (ec) fail(summary.folder, fmt::format("cannot create the folder ({})", ec.message()));
    if (!fs::is_directory(summary.folder))
      fail(summary.folder, "cannot create the folder (a file is in the way)");
  }

  const std::vector<BodySurface> surfaces = bodySurfaces(run, options);
  PolyData bodies{.triangles = true,
                  .point_doubles = {{"velocity", 3, {}}},
                  .cell_ints = {{"body_id", {}}, {"shape_id", {}}}};
  PolyData joints{
      .point_doubles = {{"joint_error", 1, {}}, {"joint_coordinate", 1, {}}, {"axis", 3, {}}},
      .point_ints = {{"joint_id", {}}, {"body1", {}}, {"body2", {}}}};
  PolyData contacts{
      .point_doubles = {{"normal", 3, {}}, {"depth", 1, {}}, {"normal_impulse", 1, {}}},
      .point_ints = {{"body1", {}}, {"body2", {}}}};
  const bool with_joints = !run.joints.empty(), with_contacts = run.has_contacts;

  std::size_t digits = 6;
  for (std::size_t n = run.frames.size(); n >= 1000000; n /= 10) ++digits;

  TempFiles files;
  std::set<std::string> written;
  std::ofstream pvd = files.open(summary.collection);
  pvd << "<?xml version=\"1.0\"?>\n"
      << "<!-- linx run: part 0 bodies" << (with_joints ? ", part 1 joints" : "")
      << (with_contacts ? fmt::format(", part {} contacts", with_joints ? 2 : 1) : "")
      << "; docs/visualization.md -->\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\""
      << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
      << "\">\n  <Collection>\n";

  const auto writePart = [&](const char* part, int number, std::size_t f, const PolyData& data) {
    const std::string name = fmt::format("{}_{:0{}}.vtp", part, f, digits);
    const fs::path path = summary.folder / name;
    std::ofstream out = files.open(path);
    data.write(out, run.frames[f].time);
    TempFiles::close(out, path);
    written.insert(name);
    pvd << fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"vtk/{}\"/>\n",
                       run.frames[f].time, number, name);
  };
  for (std::size_t f = 0; f < run.frames.size(); ++f) {
    const Frame& frame = run.frames[f];
    fillBodies(bodies, run, frame, surfaces);
    writePart("bodies", 0, f, bodies);
    if (with_joints) {
      fillJoints(joints, run, frame);
      writePart("joints", 1, f, joints);
    }
    if (with_contacts) {
      fillContacts(contacts, frame);
      writePart("contacts", with_joints ? 2 : 1, f, contacts);
    }
  }
  pvd << "  </Collection>\n</VTKFile>\n";
  TempFiles::close(pvd, summary.collection);
  files.commit();  // run.pvd last
  summary.frames = static_cast<int>(run.frames.size());

  // Frames of an earlier, longer export would otherwise linger next to this one.
  std::vector<fs::path> stale;
  std::error_code ec;
  for (fs::directory_iterator it(summary.folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_ec;
    if (ownFileName(name) && !written.count(name) && it->is_regular_file(type_ec))
      stale.push_back(it->path());
  }
  for (const fs::path& path : stale) fs::remove(path, ec);
  return summary;
}

}  // namespace linx::viz
