// `linx render DIR`: writes POV-Ray scenes of a run's frames to DIR/render, renders them to PNG
// with `povray` processes in parallel, and joins them into DIR/render.mp4 (or .gif) with `ffmpeg`.
#include "render_command.hpp"

#include "cli_common.hpp"
#include "io/output_file.hpp"
#include "process.hpp"
#include "progress.hpp"
#include "stop_signals.hpp"
#include "viz/camera.hpp"
#include "viz/povray.hpp"
#include "viz/run.hpp"

#include <linx/run_files.hpp>

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace linx::cli {

namespace fs = std::filesystem;

namespace {

constexpr int kMinSize = 16, kMaxSize = 8192;
constexpr double kMaxFps = 1000;
constexpr int kMaxJobs = 1024;

void appendFile(const fs::path& to, const fs::path& from, const std::string& heading) {
  std::ofstream out(to, std::ios::binary | std::ios::app);
  std::ifstream in(from, std::ios::binary);
  out << "==== " << heading << " ====\n" << in.rdbuf() << "\n";
}

struct Job {
  std::string name;  // "frame_000012"
  fs::path pov, part, png, log;
  std::size_t frame = 0;
};

struct Interrupted {};

// A job that failed: which frame, and the end of its log.
class JobFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs povray on every job, at most `parallel` at once; completed PNGs are renamed from their
// temporary names. Throws Interrupted on a signal and JobFailed when povray fails; either way the
// processes still running are stopped and their partial files removed.
void runJobs(const std::string& povray, const std::vector<Job>& jobs, const fs::path& folder,
             int parallel, int threads_each, const RenderOptions& options, const viz::Run& run,
             ProgressBar& progress) {
  const fs::path combined_log = folder / "povray.log";
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0, done = 0;
  std::string failure;

  const auto stopAll = [&] {
    std::vector<pid_t> pids;
    for (const auto& [pid, j] : running) pids.push_back(pid);
    stopChildren(pids);
    for (const auto& [pid, j] : running) {
      std::error_code ec;
      fs::remove(jobs[j].part, ec);
      fs::remove(jobs[j].log, ec);
      // What POV-Ray keeps to continue an interrupted render (+C); not used here.
      fs::remove(folder / (jobs[j].name + ".part.pov-state"), ec);
    }
    running.clear();
  };

  // The next job that has ended, with its wait status, or nothing when all still run. Only the
  // jobs' own pids are waited for, so that no other child of linx is reaped by mistake.
  const auto ended = [&](int& status) -> std::optional<std::map<pid_t, std::size_t>::iterator> {
    for (auto it = running.begin(); it != running.end(); ++it) {
      if (hasEnded(it->first, status, "povray")) return it;
    }
    return std::nullopt;
  };

  progress.update(0);
  while (next < jobs.size() || !running.empty()) {
    while (!StopSignals::received() && failure.empty() && next < jobs.size() &&
           running.size() < static_cast<std::size_t>(parallel)) {
      const Job& job = jobs[next];
      std::vector<std::string> args{
          "+I" + job.pov.filename().string(),
          "+O" + job.part.filename().string(),
          fmt::format("+W{}", options.width),
          fmt::format("+H{}", options.height),
          "+FN",
          "-D",
          "-P",
          "-UA",
          "+Q9",
          fmt::format("+WT{}", threads_each),
      };
      if (options.antialias == "on") {
        args.insert(args.end(), {"+A0.2", "+AM2", "+R3"});
      } else {
        args.push_back("-A");
      }
      try {
        running.emplace(spawn(povray, args, folder, job.log), next);
      } catch (...) {
        stopAll();
        throw;
      }
      ++next;
    }
    if (StopSignals::received()) {
      stopAll();
      throw Interrupted{};
    }
    if (running.empty()) break;  // a failure with nothing left running
    // Polled every 20 ms rather than blocked in waitpid, so that a signal to linx alone (not to
    // its process group) stops the render at once instead of after the frames being drawn.
    int status = 0;
    std::optional<std::map<pid_t, std::size_t>::iterator> found;
    try {
      found = ended(status);
    } catch (...) {
      stopAll();
      throw;
    }
    if (!found) {
      sleepFor(std::chrono::milliseconds(20));
      continue;
    }
    const auto it = *found;
    const Job& job = jobs[it->second];
    running.erase(it);
    std::error_code ec;
    if (StopSignals::received()) {  // the terminal's Ctrl-C also reached povray
      fs::remove(job.part, ec);
      fs::remove(job.log, ec);
      stopAll();
      throw Interrupted{};
    }
    const bool ok = succeeded(status) && fs::exists(job.part, ec);
    if (ok) {
      fs::rename(job.part, job.png, ec);
      if (ec) {
        failure = fmt::format("{}: cannot write: {}", job.png.string(), ec.message());
      } else {
        appendFile(combined_log, job.log, job.name);
        fs::remove(job.log, ec);
        progress.update(static_cast<std::int64_t>(++done));
      }
    } else if (failure.empty()) {
      fs::remove(job.part, ec);
      const fs::path kept = folder / (job.name + ".log");
      fs::rename(job.log, kept, ec);
      const viz::Frame& frame = run.frames[job.frame];
      failure =
          fmt::format("{}: povray failed on recorded frame {} (t = {:.6g} s), {}: {} (log: {})",
                      job.pov.string(), job.frame, frame.time, describeStatus(status),
                      logTail(kept), kept.string());
    } else {
      fs::remove(job.part, ec);
      fs::remove(job.log, ec);
    }
    if (!failure.empty()) {
      stopAll();
      throw JobFailed(failure);
    }
  }
}

// Runs ffmpeg to join the frames (cwd `folder`) into `video`; throws on failure or a signal.
void makeVideo(const std::string& ffmpeg, const fs::path& folder, const fs::path& video,
               const std::string& format, double rate) {
  const fs::path part =
      video.parent_path() / ("." + video.stem().string() + ".part" + video.extension().string());
  std::vector<std::string> args{"-y",
                                "-hide_banner",
                                "-loglevel",
                                "error",
                                "-nostdin",
                                "-framerate",
                                fmt::format("{:.6g}", rate),
                                "-i",
                                "frame_%06d.png"};
  if (format == "gif") {
    args.insert(args.end(), {"-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse", "-loop", "0"});
  } else {
    args.insert(args.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "20", "-vf",
                             "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-movflags", "+faststart"});
  }
  args.push_back(fs::absolute(part).string());
  const fs::path log = folder / "ffmpeg.log";
  const pid_t pid = spawn(ffmpeg, args, folder, log);
  // Polled, like povray, so that a signal stops ffmpeg at once.
  int status = 0;
  std::error_code ec;
  for (;;) {
    bool done = false;
    try {
      done = hasEnded(pid, status, "ffmpeg");
    } catch (...) {
      stopChildren({pid});
      fs::remove(part, ec);
      throw;
    }
    if (done) break;
    if (StopSignals::received()) {
      stopChildren({pid});
      fs::remove(part, ec);
      throw Interrupted{};
    }
    sleepFor(std::chrono::milliseconds(20));
  }
  if (StopSignals::received()) {  // the terminal's Ctrl-C also reached ffmpeg
    fs::remove(part, ec);
    throw Interrupted{};
  }
  if (!succeeded(status) || !fs::exists(part, ec)) {
    fs::remove(part, ec);
    throw std::runtime_error(fmt::format("{}: ffmpeg failed, {}: {} (log: {})", video.string(),
                                         describeStatus(status), logTail(log), log.string()));
  }
  fs::rename(part, video, ec);
  if (ec)
    throw std::runtime_error(fmt::format("{}: cannot write: {}", video.string(), ec.message()));
}

// Removes the frames, scenes and logs of an earlier render (it may have had more frames): only
// the names a render writes (run_files.hpp), never a file of the user's in the folder.
void removeOldFrames(const fs::path& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!run_files::isFolderEntry(run_files::kRenderFrames, name)) continue;
    if (name.rfind("frame_", 0) == 0 || name.rfind(".frame_", 0) == 0 || name == "povray.log") {
      std::error_code remove_ec;
      fs::remove(it->path(), remove_ec);
    }
  }
}

// The recorded frame of `--frame`: "last", or a time (s) within the run.
std::size_t frameFlag(const viz::Run& run, const std::string& value) {
  if (value == "last") return run.frames.size() - 1;
  double t = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(value.data(), end, t);
  if (value.empty() || ec != std::errc() || ptr != end || !std::isfinite(t))
    throw BadInput(fmt::format("--frame: expected a time (s) or 'last', got '{}'", value));
  const double t0 = run.frames.front().time, t1 = run.frames.back().time;
  const double slack = 1e-9 * std::max({1.0, std::abs(t0), std::abs(t1)});
  if (t < t0 - slack || t > t1 + slack)
    throw BadInput(
        fmt::format("--frame: {} s is outside the run ({:.6g} to {:.6g} s)", value, t0, t1));
  return viz::nearestFrame(run, t);
}

void validate(const RenderOptions& o) {
  if (o.width < kMinSize || o.width > kMaxSize)
    throw BadInput(fmt::format("--width: must be an integer in [{}, {}], got {}", kMinSize,
                               kMaxSize, o.width));
  if (o.height < kMinSize || o.height > kMaxSize)
    throw BadInput(fmt::format("--height: must be an integer in [{}, {}], got {}", kMinSize,
                               kMaxSize, o.height));
  if (!(std::isfinite(o.fps) && o.fps > 0 && o.fps <= kMaxFps))
    throw BadInput(fmt::format("--fps: must be a number in (0, {}], got {}", kMaxFps, o.fps));
  if (o.jobs < 0 || o.jobs > kMaxJobs)
    throw BadInput(
        fmt::format("--jobs: must be an integer in [0, {}] (0: two per hardware "
                    "thread), got {}",
                    kMaxJobs, o.jobs));
  if (!o.video.empty() && o.video != "mp4" && o.video != "gif" && o.video != "none")
    throw BadInput(fmt::format("--video: must be mp4, gif or none, got '{}'", o.video));
  if (o.antialias != "on" && o.antialias != "off")
    throw BadInput(fmt::format("--antialias: must be on or off, got '{}'", o.antialias));
  if (!o.frame.empty() && !o.video.empty() && o.video != "none")
    throw BadInput(
        fmt::format("--video: {} needs every frame; --frame renders one picture", o.video));
}

}  // namespace

void addRenderOptions(CLI::App& cmd, RenderOptions& options) {
  cmd.add_option("dir", options.dir, "Output folder of linx run")->required();
  cmd.add_option("--width", options.width, "Picture width (pixels)")->capture_default_str();
  cmd.add_option("--height", options.height, "Picture height (pixels)")->capture_default_str();
  cmd.add_option("--fps", options.fps,
                 "Pictures per second of simulated time (at most every recorded frame)")
      ->capture_default_str();
  cmd.add_option("--frame", options.frame,
                 "Render only the frame nearest this time (s), or 'last'; prints the PNG's path");
  cmd.add_option("-j,--jobs", options.jobs, "povray processes at once (0: two per hardware thread)")
      ->capture_default_str();
  cmd.add_option("--video", options.video,
                 "mp4, gif or none (default: mp4 when ffmpeg is installed, else none)");
  cmd.add_option("--antialias", options.antialias, "on or off")->capture_default_str();
}

int render(const RenderOptions& options) {
  validate(options);
  const viz::Run run = viz::openRun(options.dir);
  if (run.frames.empty()) throw BadInput(fmt::format("{}: the run has no frames", options.dir));
  const bool single = !options.frame.empty();
  const std::size_t single_frame = single ? frameFlag(run, options.frame) : 0;

  const std::optional<std::string> povray = findProgram("povray");
  if (!povray)
    throw std::runtime_error(
        "render: povray not found on PATH (install it with scripts/install-deps.sh)");
  std::string video = options.video;
  std::optional<std::string> ffmpeg;
  if (!single && video != "none") {
    ffmpeg = findProgram("ffmpeg");
    if (!ffmpeg && !video.empty())
      throw std::runtime_error(fmt::format(
          "render: --video {}: ffmpeg not found on PATH (install it with scripts/install-deps.sh)",
          video));
    if (video.empty()) video = ffmpeg ? "mp4" : "none";
  }
  if (single) video = "none";

  const fs::path dir(options.dir);
  const fs::path folder = dir / "render";
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw std::runtime_error(fmt::format("{}: cannot create: {}", folder.string(), ec.message()));

  const double aspect = static_cast<double>(options.width) / options.height;
  const viz::Camera camera = viz::chooseCamera(run, aspect);
  io::writeFileAtomically(folder / "scene.inc", viz::povInclude(run, camera, aspect));
  // povray reads a povray.ini from its working folder, DIR/render, which a run folder from
  // elsewhere could bring (an Include_Header runs its code): POVINI names linx's own, which
  // sets nothing, as every option is on povray's command line.
  const fs::path ini = folder / "linx.ini";
  io::writeFileAtomically(ini, "; linx render: povray's options are on its command line\n");
  // By its plain name: povray runs in that folder, and reads the variable as an option, so a
  // folder path holding spaces, brackets or '&' would be an option it cannot set.
  ::setenv("POVINI", ini.filename().c_str(), 1);

  const std::vector<std::size_t> frames =
      single ? std::vector<std::size_t>{single_frame} : viz::pickFrames(run, options.fps);
  if (!single) removeOldFrames(folder);
  std::vector<Job> jobs;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    Job job;
    job.frame = frames[k];
    job.name = single ? fmt::format("still_{:06d}", frames[k]) : fmt::format("frame_{:06d}", k);
    job.pov = folder / (job.name + ".pov");
    job.part = folder / (job.name + ".part.png");
    job.png = folder / (job.name + ".png");
    job.log = folder / ("." + job.name + ".log");
    io::writeFileAtomically(job.pov, viz::povFrame(run, job.frame, "scene.inc"));
    jobs.push_back(std::move(job));
  }

  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // Each povray process idles about 0.7 s at its start (measured with POV-Ray 3.7): two per
  // hardware thread keep the cores busy.
  const int jobs_flag = options.jobs > 0 ? options.jobs : 2 * hardware;
  const int parallel = std::max(1, std::min(jobs_flag, static_cast<int>(jobs.size())));
  const int threads_each = std::max(1, jobs_flag / parallel);

  const StopSignals stop_signals;
  {
    ProgressBar progress(isatty(fileno(stderr)) ? stderr : nullptr,
                         static_cast<std::int64_t>(jobs.size()), std::string("frame"));
    try {
      if (!single) {
        std::error_code remove_ec;
        fs::remove(folder / "povray.log", remove_ec);
      }
      runJobs(*povray, jobs, folder, parallel, threads_each, options, run, progress);
    } catch (const Interrupted&) {
      progress.clear();
      say(stderr, "linx: {}: interrupted; stopped povray\n", folder.string());
      return kExitInterrupted;
    } catch (const JobFailed& e) {
      progress.clear();
      throw std::runtime_error(e.what());
    }
  }

  if (single) {
    say("{}\n", jobs.front().png.string());
    return 0;
  }

  std::string video_note;
  if (video == "none") {
    video_note = options.video == "none" ? "" : ", no video (ffmpeg not found)";
  } else {
    // Played at the simulated speed: the picked frames' own rate where the run recorded fewer.
    double rate = options.fps;
    const double span = run.frames[frames.back()].time - run.frames[frames.front()].time;
    if (frames.size() > 1 && span > 0)
      rate = std::min(rate, static_cast<double>(frames.size() - 1) / span);
    const fs::path file = dir / ("render." + video);
    try {
      makeVideo(*ffmpeg, folder, file, video, rate);
    } catch (const Interrupted&) {
      say(stderr, "linx: {}: interrupted; stopped ffmpeg\n", file.string());
      return kExitInterrupted;
    }
    video_note = fmt::format(", video {}", file.string());
  }
  say("rendered {} frame{} to {} ({}x{}){}\n", frames.size(), frames.size() == 1 ? "" : "s",
      folder.string(), options.width, options.height, video_note);
  return 0;
}

}  // namespace linx::cli
