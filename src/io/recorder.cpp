// CSV trajectory and report writer. Rows go to hidden temporary files (DIR/.bodies.csv.tmp, ...)
// that commit() renames to their final names; without a commit the temporary files, and any
// directory the recorder created, are removed. Numbers are written in the shortest form that reads
// back to the same double (full precision).
#include <linx/recorder.hpp>

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace linx {

namespace fs = std::filesystem;

namespace {

enum Output { kBodies, kJoints, kWorld, kContacts, kBreaks, kOutputCount };

constexpr std::array<std::string_view, kOutputCount> kFileNames = {
    "bodies.csv", "joints.csv", "world.csv", "contacts.csv", "breaks.csv"};
constexpr std::array<std::string_view, kOutputCount> kHeaders = {
    "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz",
    "time,joint,coordinate,error,fx,fy,fz,tx,ty,tz,coordinate2,coordinate3,coordinate4,coordinate5,"
    "coordinate6",
    "time,kinetic_energy,potential_energy,total_energy,max_joint_error,solver_iterations,residual",
    "time,body1,body2,x,y,z,nx,ny,nz,depth,normal_impulse",
    "time,step,joint,fx,fy,fz,tx,ty,tz",
};

// A name as one CSV field: quoted when it holds a separator, a quote or a line break.
std::string csvField(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

std::runtime_error ioError(std::string_view what, const fs::path& path, int error) {
  return std::runtime_error(
      fmt::format("cannot {} {}: {}", what, path.string(), std::generic_category().message(error)));
}

}  // namespace

struct Recorder::Files {
  std::array<std::FILE*, kOutputCount> file{};
  std::array<fs::path, kOutputCount> temp;
  std::vector<fs::path> created_dirs;                      // innermost first
  std::vector<std::pair<std::string, std::string>> extra;  // addFile(): name, text
  std::vector<fs::path> extra_temp;                        // their temporary files, once written
  bool keep = false;

  // Closes the files; without a commit also deletes them and the directories created for them.
  ~Files() {
    for (std::FILE* f : file) {
      if (f) std::fclose(f);
    }
    if (keep) return;
    std::error_code ignored;
    for (const fs::path& p : temp)
      if (!p.empty()) fs::remove(p, ignored);
    for (const fs::path& p : extra_temp) fs::remove(p, ignored);
    for (const fs::path& d : created_dirs) fs::remove(d, ignored);  // only removes empty ones
  }
};

Recorder::Recorder(const fs::path& dir, const RecorderOptions& options)
    : dir_(dir), files_(std::make_unique<Files>()) {
  // Note which directories are missing, so that a run without a commit leaves no trace.
  std::error_code ec;
  for (fs::path d = fs::absolute(dir_, ec); !ec && !fs::exists(d, ec) && !ec; d = d.parent_path()) {
    files_->created_dirs.push_back(d);
    if (d == d.parent_path()) break;
  }
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) {
    throw ioError("create the output directory", dir_, ec ? ec.value() : ENOTDIR);
  }
  for (int i = 0; i < kOutputCount; ++i) {
    if ((i == kContacts && !options.contacts) || (i == kBreaks && !options.breaks)) continue;
    files_->temp[i] = dir_ / fmt::format(".{}.tmp", kFileNames[i]);
    files_->file[i] = std::fopen(files_->temp[i].c_str(), "wb");
    if (!files_->file[i]) throw ioError("create", files_->temp[i], errno);
    fmt::print(files_->file[i], "{}\n", kHeaders[i]);
  }
}

Recorder::~Recorder() = default;

void Recorder::record(const World& world) {
  if (committed_) throw std::logic_error("Recorder::record after commit");
  const double t = world.time();

  std::FILE* bodies = files_->file[kBodies];
  for (int i = 0; i < world.bodyCount(); ++i) {
    const Body& b = world.body(BodyId{i});
    const Vec3& p = b.position();
    const Quat& q = b.orientation();
    const Vec3& v = b.linearVelocity();
    const Vec3& w = b.angularVelocity();
    fmt::print(bodies, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", t, csvField(b.name()),
               p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z(), w.x(), w.y(),
               w.z());
  }

  std::FILE* joints = files_->file[kJoints];
  for (int i = 0; i < world.jointCount(); ++i) {
    const JointId id{i};
    // The first coordinate after the name; the others (of joints with several) at the end.
    const JointCoordinates q = world.jointCoordinates(id);
    std::string coordinate[kMaxCoordinates];
    for (Eigen::Index k = 0; k < q.size(); ++k) coordinate[k] = fmt::format("{}", q[k]);
    const JointReaction r = world.jointReaction(id);
    fmt::print(joints, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", t,
               csvField(world.joint(id).name()), coordinate[0], world.jointError(id), r.force.x(),
               r.force.y(), r.force.z(), r.torque.x(), r.torque.y(), r.torque.z(), coordinate[1],
               coordinate[2], coordinate[3], coordinate[4], coordinate[5]);
  }

  const Energy e = world.energy();
  const SolverReport& report = world.lastReport();
  fmt::print(files_->file[kWorld], "{},{},{},{},{},{},{}\n", t, e.kinetic, e.potential, e.total(),
             world.maxJointError(), report.iterations, report.residual);

  if (std::FILE* breaks = files_->file[kBreaks]) {
    const auto all = world.jointBreaks();
    for (; breaks_written_ < all.size(); ++breaks_written_) {
      const JointBreak& b = all[breaks_written_];
      const JointReaction& r = b.reaction;
      fmt::print(breaks, "{},{},{},{},{},{},{},{},{}\n", b.time, b.step,
                 csvField(world.joint(b.joint).name()), r.force.x(), r.force.y(), r.force.z(),
                 r.torque.x(), r.torque.y(), r.torque.z());
    }
  }

  if (std::FILE* contacts = files_->file[kContacts]) {
    for (const Contact& c : world.contacts()) {
      fmt::print(contacts, "{},{},{},{},{},{},{},{},{},{},{}\n", t,
                 csvField(world.body(c.body1).name()), csvField(world.body(c.body2).name()),
                 c.point.x(), c.point.y(), c.point.z(), c.normal.x(), c.normal.y(), c.normal.z(),
                 c.depth, c.normal_impulse);
    }
  }
}

void Recorder::addFile(const std::string& name, std::string text) {
  if (committed_) throw std::logic_error("Recorder::addFile after commit");
  if (name.empty() || name.find('/') != std::string::npos || name.front() == '.')
    throw std::invalid_argument(
        fmt::format("Recorder::addFile: '{}' is not a plain file name", name));
  files_->extra.emplace_back(name, std::move(text));
}

void Recorder::commit() {
  if (committed_) return;
  for (const auto& [name, text] : files_->extra) {
    const fs::path temp = dir_ / fmt::format(".{}.tmp", name);
    std::FILE* f = std::fopen(temp.c_str(), "wb");
    if (!f) throw ioError("create", temp, errno);
    files_->extra_temp.push_back(temp);
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !written) throw ioError("write", temp, errno);
  }
  for (int i = 0; i < kOutputCount; ++i) {
    std::FILE* f = std::exchange(files_->file[i], nullptr);
    if (!f) continue;  // an output not asked for
    const bool failed = std::ferror(f) != 0;
    if (std::fclose(f) != 0 || failed) throw ioError("write", files_->temp[i], errno);
  }
  for (int i = 0; i < kOutputCount; ++i) {
    if (files_->temp[i].empty()) continue;
    const fs::path final_path = dir_ / kFileNames[i];
    std::error_code ec;
    fs::rename(files_->temp[i], final_path, ec);
    if (ec) throw ioError("rename to", final_path, ec.value());
  }
  for (std::size_t i = 0; i < files_->extra.size(); ++i) {
    const fs::path final_path = dir_ / files_->extra[i].first;
    std::error_code ec;
    fs::rename(files_->extra_temp[i], final_path, ec);
    if (ec) throw ioError("rename to", final_path, ec.value());
  }
  files_->extra_temp.clear();
  // A contacts.csv or breaks.csv left by an earlier run would not belong to this one.
  for (const Output optional : {kContacts, kBreaks}) {
    if (!files_->temp[optional].empty()) continue;
    std::error_code ec;
    fs::remove(dir_ / kFileNames[optional], ec);
  }
  files_->keep = true;
  committed_ = true;
}

}  // namespace linx
