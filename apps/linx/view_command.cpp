#include "view_command.hpp"

#include <sys/socket.h>

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

#include "cli_common.hpp"
#include "process.hpp"
#include "stop_signals.hpp"
#include "viz/run.hpp"

#include <linx/run_files.hpp>

// Last: through <resolv.h> it defines the macro `_res`, which breaks Eigen included after it.
#include <httplib.h>

namespace linx::cli {

// The page: viewer/ bundled into one HTML file by viewer/build.mjs (generated viewer_page.cpp).
extern const unsigned char kViewerPage[];
extern const std::size_t kViewerPageSize;

namespace {

// Whether `name` is one of the files served from the run folder: those of the run file list that
// are read back (docs/scene-format.md, "Outputs").
bool servedRunFile(std::string_view name) {
  for (const run_files::RunFile& f : run_files::kAll)
    if (f.read_back && f.name == name) return true;
  return false;
}

std::string jsonString(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
        else
          out += c;
    }
  }
  return out + "\"";
}

bool readFile(const std::filesystem::path& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream text;
  text << in.rdbuf();
  out = std::move(text).str();
  return !in.bad();
}

// Which run files exist, and the folder's name: what the page fetches first.
std::string manifest(const std::filesystem::path& dir) {
  std::string files;
  for (const run_files::RunFile& file : run_files::kAll) {
    if (!file.read_back) continue;
    const std::string_view name = file.name;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(dir / name, ec)) continue;
    files += (files.empty() ? "" : ",") + jsonString(name);
  }
  const std::filesystem::path abs = std::filesystem::absolute(dir).lexically_normal();
  std::string name = abs.filename().string();
  if (name.empty()) name = abs.parent_path().filename().string();
  return fmt::format("{{\"name\":{},\"files\":[{}]}}\n", jsonString(name), files);
}

// Sends `size` bytes at `data` (kept alive by `owner`) uncompressed and not cached. A sized
// content provider: cpp-httplib would otherwise brotli-compress text at its slowest setting, which
// takes seconds for the page and minutes for a large CSV file.
void reply(httplib::Response& res, const char* data, std::size_t size, const char* type,
           std::shared_ptr<const std::string> owner = nullptr) {
  res.set_header("Cache-Control", "no-store");
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
  const viz::Run run = viz::readRun(options.dir);
  const std::filesystem::path dir = options.dir;

  httplib::Server server;
  server.set_keep_alive_timeout(1);
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
    if (host == fmt::format("127.0.0.1:{}", port) || host == fmt::format("localhost:{}", port))
      return httplib::Server::HandlerResponse::Unhandled;
    res.status = 403;
    res.set_content("linx view: forbidden host\n", "text/plain");
    return httplib::Server::HandlerResponse::Handled;
  });
  server.Get("/", [](const httplib::Request&, httplib::Response& res) {
    reply(res, reinterpret_cast<const char*>(kViewerPage), kViewerPageSize,
          "text/html; charset=utf-8");
  });
  server.Get("/run/manifest.json", [&dir](const httplib::Request&, httplib::Response& res) {
    const auto body = std::make_shared<const std::string>(manifest(dir));
    reply(res, body->data(), body->size(), "application/json", body);
  });
  // The run's files by their fixed names only: the pattern admits no '/' and the name must be
  // one of the run files read back, so nothing outside DIR can be reached.
  server.Get(R"(/run/([a-z]+\.(?:json|csv)))", [&dir](const httplib::Request& req,
                                                      httplib::Response& res) {
    const std::string name = req.matches[1];
    const bool known = servedRunFile(name);
    auto body = std::make_shared<std::string>();
    if (!known || !readFile(dir / name, *body)) {
      res.status = 404;
      res.set_content(fmt::format("linx view: no {} in the run folder\n", name), "text/plain");
      return;
    }
    reply(res, body->data(), body->size(),
          name.ends_with(".json") ? "application/json" : "text/csv; charset=utf-8", body);
  });

  if (options.port == 0) {
    port = server.bind_to_any_port("127.0.0.1");
    if (port < 0) throw std::runtime_error("cannot listen on 127.0.0.1 (no free port?)");
  } else if (!server.bind_to_port("127.0.0.1", options.port)) {
    throw BadInput(
        fmt::format("--port: cannot listen on 127.0.0.1:{} (already in use?)", options.port));
  }

  const StopSignals stop_signals;
  std::atomic<bool> ended{false};
  bool listened = true;
  std::thread serving([&] {
    listened = server.listen_after_bind();
    ended = true;
  });
  std::cout << fmt::format("linx view: http://127.0.0.1:{}/ (Ctrl-C to stop)", port) << std::endl;
  std::cerr << fmt::format("linx view: {} ({} bodies, {} frames)", options.dir, run.bodies.size(),
                           run.frames.size())
            << std::endl;

  int received = 0;
  while (!ended && (received = StopSignals::received()) == 0)
    sleepFor(std::chrono::milliseconds(50));
  server.stop();
  serving.join();
  if (!received && !listened) throw std::runtime_error("the viewer's server stopped unexpectedly");
  std::cerr << "linx view: stopped" << std::endl;
  return 0;
}

}  // namespace linx::cli
