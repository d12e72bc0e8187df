// CSV trajectory and report writer. The files are opened through a descriptor of the output folder
// taken once (openat, unlinkat, renameat), so that the folder being renamed or replaced during a
// run can never make the recorder write or delete elsewhere. Each frame is formatted into one
// buffer per file and written with write(2) before record() returns. Numbers are written in the
// shortest form that reads back to the same double (full precision).
#include <linx/recorder.hpp>
#include <linx/run_files.hpp>

#include "io/output_file.hpp"
#include "io/run_folder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace linx {

namespace fs = std::filesystem;
using io::ioError;
using io::writeAll;

namespace {

enum Output { kBodies, kJoints, kWorld, kContacts, kBreaks, kOutputCount };

constexpr std::array<run_files::RunFile, kOutputCount> kOutputs = {
    run_files::kBodies, run_files::kJoints, run_files::kWorld, run_files::kContacts,
    run_files::kBreaks};

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

// Opens the output folder and takes its lock (io::tryLockFolder): one writer at a time.
int openLocked(const fs::path& dir, int create_error) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw ioError("open the output folder", dir, create_error ? create_error : errno);
  try {
    // Where the file system has no locks, the folder is written unlocked, as it can only be.
    if (io::tryLockFolder(fd, dir) == io::FolderLock::kHeld)
      throw RunFolderError(fmt::format(
          "{}: another run or recording is writing into this folder (it holds the folder's "
          "lock); wait for it to end, or choose another folder",
          dir.string()));
  } catch (...) {
    ::close(fd);
    throw;
  }
  return fd;
}

}  // namespace

struct Recorder::Files {
  int dir_fd = -1;
  std::array<int, kOutputCount> fd{-1, -1, -1, -1, -1};
  std::array<std::string, kOutputCount> buffer;

  ~Files() { close(); }

  void close() {
    for (int& f : fd) {
      if (f >= 0) ::close(f);
      f = -1;
    }
    if (dir_fd >= 0) ::close(dir_fd);
    dir_fd = -1;
  }
};

Recorder::Recorder(const fs::path& dir, const RecorderOptions& options)
    : dir_(dir), files_(std::make_unique<Files>()) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  Files& f = *files_;
  f.dir_fd = openLocked(dir_, ec ? ec.value() : 0);

  // A folder of the user's where this run writes a file is refused before anything is removed.
  const auto writes = [&](int i) {
    return !((i == kContacts && !options.contacts) || (i == kBreaks && !options.breaks));
  };
  for (int i = -1; i < kOutputCount; ++i) {
    if (i >= 0 && !writes(i)) continue;
    const std::string name(i < 0 ? run_files::kScene.name : kOutputs[i].name);
    struct stat st {};
    if (::fstatat(f.dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISDIR(st.st_mode))
      throw RunFolderError(fmt::format(
          "{}: a folder where the run writes its file {}: linx leaves it alone; move it, or "
          "choose another folder",
          (dir_ / name).string(), name));
  }
  // An earlier run's files, scene.json first: a folder with a scene.json never mixes two runs.
  io::clearEarlierRun(f.dir_fd, dir_);
  for (int i = 0; i < kOutputCount; ++i) {
    if (!writes(i)) continue;
    const std::string name(kOutputs[i].name);
    f.fd[i] = ::openat(f.dir_fd, name.c_str(),
                       O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (f.fd[i] < 0) throw ioError("create", dir_ / name, errno);
    const std::string header = fmt::format("{}\n", kOutputs[i].header);
    writeAll(f.fd[i], header, dir_ / name);
    position_.bytes[static_cast<std::size_t>(i)] = header.size();
  }
}

Recorder::Recorder(const fs::path& dir, const RecorderOptions& options, const RecorderPosition& at)
    : dir_(dir), files_(std::make_unique<Files>()), position_(at) {
  Files& f = *files_;
  f.dir_fd = openLocked(dir_, 0);
  for (int i = 0; i < kOutputCount; ++i) {
    if ((i == kContacts && !options.contacts) || (i == kBreaks && !options.breaks)) continue;
    const fs::path path = dir_ / kOutputs[i].name;
    const std::string name(kOutputs[i].name);
    f.fd[i] = ::openat(f.dir_fd, name.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    if (f.fd[i] < 0)
      throw RunFolderError(fmt::format(
          "{}: {}", path.string(),
          errno == ENOENT ? std::string("missing") : std::generic_category().message(errno)));
    struct stat st {};
    const std::uint64_t size = at.bytes[static_cast<std::size_t>(i)];
    if (::fstat(f.fd[i], &st) != 0) throw ioError("reopen", path, errno);
    if (!S_ISREG(st.st_mode)) throw RunFolderError(fmt::format("{}: not a file", path.string()));
    if (static_cast<std::uint64_t>(st.st_size) < size)
      throw RunFolderError(
          fmt::format("{}: {} bytes, shorter than the {} the checkpoint's run had "
                      "written (not this run's file?)",
                      path.string(), st.st_size, size));
    // The header this run wrote: a file of another kind, or of another version, is not its own.
    const std::string header = fmt::format("{}\n", kOutputs[i].header);
    std::string first(header.size(), '\0');
    const ssize_t n = ::pread(f.fd[i], first.data(), first.size(), 0);
    if (n != static_cast<ssize_t>(first.size()) || first != header)
      throw RunFolderError(
          fmt::format("{}: its first line is not the header '{}' (not this "
                      "run's file?)",
                      path.string(), kOutputs[i].header));
    if (size < header.size())
      throw RunFolderError(
          fmt::format("{}: the checkpoint's run had written {} bytes, less than "
                      "the header",
                      path.string(), size));
  }
  // Every file checked first: a folder that is not the checkpoint's run is left as it was.
  for (int i = 0; i < kOutputCount; ++i) {
    if (f.fd[i] < 0) continue;
    const auto size = static_cast<off_t>(at.bytes[static_cast<std::size_t>(i)]);
    if (::ftruncate(f.fd[i], size) != 0 || ::lseek(f.fd[i], size, SEEK_SET) < 0)
      throw ioError("cut back", dir_ / kOutputs[i].name, errno);
  }
}

Recorder::~Recorder() = default;

void Recorder::record(const World& world) {
  if (finished_) throw std::logic_error("Recorder::record after finish");
  const double t = world.time();
  std::array<std::string, kOutputCount>& out = files_->buffer;
  for (std::string& b : out) b.clear();

  auto bodies = std::back_inserter(out[kBodies]);
  for (int i = 0; i < world.bodyCount(); ++i) {
    const Body& b = world.body(BodyId{i});
    const Vec3& p = b.position();
    const Quat& q = b.orientation();
    const Vec3& v = b.linearVelocity();
    const Vec3& w = b.angularVelocity();
    fmt::format_to(bodies, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", t, csvField(b.name()),
                   p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z(), w.x(),
                   w.y(), w.z());
  }

  auto joints = std::back_inserter(out[kJoints]);
  for (int i = 0; i < world.jointCount(); ++i) {
    const JointId id{i};
    // The first coordinate after the name; the others (of joints with several) at the end.
    const JointCoordinates q = world.jointCoordinates(id);
    std::string coordinate[kMaxCoordinates];
    for (Eigen::Index k = 0; k < q.size(); ++k) coordinate[k] = fmt::format("{}", q[k]);
    const JointReaction r = world.jointReaction(id);
    fmt::format_to(joints, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", t,
                   csvField(world.joint(id).name()), coordinate[0], world.jointError(id),
                   r.force.x(), r.force.y(), r.force.z(), r.torque.x(), r.torque.y(), r.torque.z(),
                   coordinate[1], coordinate[2], coordinate[3], coordinate[4], coordinate[5]);
  }

  const Energy e = world.energy();
  const SolverReport& report = world.lastReport();
  fmt::format_to(std::back_inserter(out[kWorld]), "{},{},{},{},{},{},{}\n", t, e.kinetic,
                 e.potential, e.total(), world.maxJointError(), report.iterations, report.residual);

  if (files_->fd[kBreaks] >= 0) {
    const auto all = world.jointBreaks();
    for (; position_.breaks < all.size(); ++position_.breaks) {
      const JointBreak& b = all[position_.breaks];
      const JointReaction& r = b.reaction;
      fmt::format_to(std::back_inserter(out[kBreaks]), "{},{},{},{},{},{},{},{},{}\n", b.time,
                     b.step, csvField(world.joint(b.joint).name()), r.force.x(), r.force.y(),
                     r.force.z(), r.torque.x(), r.torque.y(), r.torque.z());
    }
  }

  if (files_->fd[kContacts] >= 0) {
    auto contacts = std::back_inserter(out[kContacts]);
    for (const Contact& c : world.contacts()) {
      fmt::format_to(contacts, "{},{},{},{},{},{},{},{},{},{},{}\n", t,
                     csvField(world.body(c.body1).name()), csvField(world.body(c.body2).name()),
                     c.point.x(), c.point.y(), c.point.z(), c.normal.x(), c.normal.y(),
                     c.normal.z(), c.depth, c.normal_impulse);
    }
  }

  for (int i = 0; i < kOutputCount; ++i) {
    if (files_->fd[i] < 0) continue;
    writeAll(files_->fd[i], out[i], dir_ / kOutputs[i].name);
    position_.bytes[static_cast<std::size_t>(i)] += out[i].size();
  }
}

void Recorder::writeFile(const std::string& name, const std::string& text) {
  if (finished_) throw std::logic_error("Recorder::writeFile after finish");
  if (name.empty() || name.find('/') != std::string::npos || name.front() == '.')
    throw std::invalid_argument(
        fmt::format("Recorder::writeFile: '{}' is not a plain file name", name));
  io::writeFileAtomically(name, text, files_->dir_fd, dir_ / name);
}

void Recorder::finish() {
  if (finished_) return;
  finished_ = true;
  Files& f = *files_;
  for (int i = 0; i < kOutputCount; ++i) {
    if (f.fd[i] < 0) continue;
    const int fd = std::exchange(f.fd[i], -1);
    int error = ::fsync(fd) == 0 ? 0 : errno;
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) throw ioError("write", dir_ / kOutputs[i].name, error);
  }
  ::fsync(f.dir_fd);  // the files' names; a failure here loses nothing a crash would not
  f.close();
}

}  // namespace linx
