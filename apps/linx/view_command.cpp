#include "view_command.hpp"

#include <sys/socket.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "process.hpp"
#include "stop_signals.hpp"
#include "viz/run.hpp"

#include <linx/run_files.hpp>

// Last: through <resolv.h> it defines the macro `_res`, which breaks Eigen included after it.
#include "view_server.hpp"  // <httplib.h>

namespace linx::cli {

// The page: viewer/ bundled into one HTML file by viewer/build.mjs (generated viewer_page.cpp).
extern const unsigned char kViewerPage[];
extern const std::size_t kViewerPageSize;

namespace {

constexpr std::size_t kMaxRanges = 4;

// JSON text through nlohmann-json only; bytes that are not UTF-8 (a folder's name) become U+FFFD.
std::string jsonText(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// The run's files, opened once when the server starts: only these are served, always the files
// that were there then (O_NOFOLLOW: a link is not one of them), read through their descriptors,
// so that a file renamed, replaced or turned into a link later cannot be served in its place. A
// file still being written (a run in progress) is served as far as it has grown.
class RunFiles {
 public:
  explicit RunFiles(const std::filesystem::path& dir) {
    for (const run_files::RunFile& file : run_files::kAll) {
      if (!file.read_back) continue;
      const std::string name(file.name);
      const int fd = ::open((dir / name).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat st {};
      if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        continue;
      }
      files_.emplace_back(name, fd);
    }
  }
  ~RunFiles() {
    for (const auto& [name, fd] : files_) ::close(fd);
  }
  RunFiles(const RunFiles&) = delete;
  RunFiles& operator=(const RunFiles&) = delete;

  /// The file's bytes now, or false for a name that is not served.
  bool read(std::string_view name, std::string& out) const {
    for (const auto& [served, fd] : files_) {
      if (served != name) continue;
      struct stat st {};
      if (::fstat(fd, &st) != 0) return false;
      out.resize(static_cast<std::size_t>(st.st_size));
      std::size_t done = 0;
      while (done < out.size()) {
        const ssize_t n =
            ::pread(fd, out.data() + done, out.size() - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
      out.resize(done);
      return true;
    }
    return false;
  }

  /// Which run files are served, and the folder's name: what the page fetches first.
  std::string manifest(const std::filesystem::path& dir) const {
    nlohmann::json names = nlohmann::json::array();
    for (const auto& [name, fd] : files_) names.push_back(name);
    const std::filesystem::path abs = std::filesystem::absolute(dir).lexically_normal();
    std::string folder = abs.filename().string();
    if (folder.empty()) folder = abs.parent_path().filename().string();
    nlohmann::json manifest;
    manifest["name"] = folder;
    manifest["files"] = names;
    return jsonText(manifest) + "\n";
  }

 private:
  std::vector<std::pair<std::string, int>> files_;
};

// Sends `size` bytes at `data` (kept alive by `owner`) uncompressed and not cached. A sized
// content provider: cpp-httplib would otherwise brotli-compress text at its slowest setting, which
// takes seconds for the page and minutes for a large CSV file.
// Byte ranges are checked against the size first (fitRanges), at most kMaxRanges of them (800
// made a 421 MB answer).
void reply(const httplib::Request& req, httplib::Response& res, const char* data, std::size_t size,
           const char* type, std::shared_ptr<const std::string> owner = nullptr) {
  res.set_header("Cache-Control", "no-store");
  if (!fitRanges(req, size, kMaxRanges, res)) return;
  res.set_content_provider(
      size, type, [data, owner](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
        return sink.write(data + offset, length);
      });
}

}  // namespace

void addViewOptions(CLI::App& cmd, ViewOptions& options) {
  cmd.add_option("dir", options.dir, "Output folder of linx run")->required();
  cmd.add_option("--port", options.port, "Port on 127.0.0.1 (0: any free port)")
      ->default_val(0)
      ->type_name("N");
}

int view(const ViewOptions& options) {
  if (options.port < 0 || options.port > 65535)
    throw BadInput(fmt::format("--port: must be an integer in [0, 65535], got {}", options.port));
  // Check the folder up front: a bad run is reported now (exit 2), not in the browser.
  const viz::Run run = viz::openRun(options.dir);
  const std::filesystem::path dir = options.dir;

  const RunFiles files(dir);

  // Deadlines for whole requests, a cap per client address, enough workers (ViewServerLimits):
  // a client trickling or holding connections is dropped within seconds, and never holds the
  // server from the others.
  ViewServer server;
  // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, with which a second server could
  // share a port that is taken instead of being refused.
  server.set_socket_options([](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });  // quick shutdown while a browser keeps its connections
  int port = options.port;

  // Only requests addressed to this server by name (no DNS rebinding from other sites).
  server.set_pre_routing_handler([&port](const httplib::Request& req, httplib::Response& res) {
    const std::string host = req.get_header_value("Host");
    if (host != fmt::format("127.0.0.1:{}", port) && host != fmt::format("localhost:{}", port)) {
      dropRanges(req);
      res.status = 403;
      res.set_content("linx view: forbidden host\n", "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  server.Get("/", [](const httplib::Request& req, httplib::Response& res) {
    reply(req, res, reinterpret_cast<const char*>(kViewerPage), kViewerPageSize,
          "text/html; charset=utf-8");
  });
  server.Get("/run/manifest.json",
             [&dir, &files](const httplib::Request& req, httplib::Response& res) {
               const auto body = std::make_shared<const std::string>(files.manifest(dir));
               reply(req, res, body->data(), body->size(), "application/json", body);
             });
  // The run's files by their fixed names only: the pattern admits no '/' and the name must be
  // one of the run files opened at the start (RunFiles), so nothing else can be reached.
  server.Get(R"(/run/([a-z]+\.(?:json|csv)))", [&files](const httplib::Request& req,
                                                        httplib::Response& res) {
    const std::string name = req.matches[1];
    auto body = std::make_shared<std::string>();
    if (!files.read(name, *body)) {
      dropRanges(req);
      res.status = 404;
      res.set_content(fmt::format("linx view: no {} in the run folder\n", name), "text/plain");
      return;
    }
    reply(req, res, body->data(), body->size(),
          name.ends_with(".json") ? "application/json" : "text/csv; charset=utf-8", body);
  });

  if (options.port == 0) {
    port = server.bind_to_any_port("127.0.0.1");
    if (port < 0) throw std::runtime_error("cannot listen on 127.0.0.1 (no free port?)");
  } else if (!server.bind_to_port("127.0.0.1", options.port)) {
    throw BadInput(
        fmt::format("--port: cannot listen on 127.0.0.1:{} (already in use?)", options.port));
  }
  server.widenBacklog();

  const StopSignals stop_signals;
  std::atomic<bool> ended{false};
  bool listened = true;
  std::thread serving([&] {
    listened = server.listen_after_bind();
    ended = true;
  });
  say("linx view: http://127.0.0.1:{}/ (Ctrl-C to stop)\n", port);
  say(stderr, "linx view: {} ({} bodies, {} frames)\n", options.dir, run.bodies.size(),
      run.frames.size());

  int received = 0;
  while (!ended && (received = StopSignals::received()) == 0)
    sleepFor(std::chrono::milliseconds(50));
  server.stop();
  serving.join();
  if (!received && !listened) throw std::runtime_error("the viewer's server stopped unexpectedly");
  say(stderr, "linx view: stopped\n");
  return 0;
}

}  // namespace linx::cli
