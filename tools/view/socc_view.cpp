// socc-view: a live view of the shared map. Listens to what map_server and the robots publish
// over LCM (SOCC/MAP_DELTA, SOCC/STATUS, SOCC/INTEGRATE/REQ) and serves a 3D page (three.js)
// and the Foxglove WebSocket protocol. A separate process that only listens: a slow or gone
// browser never slows the map server. See docs/view.md.
#include <CLI/CLI.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "access_token.hpp"
#include "lcm_feed.hpp"
#include "socc/auth/shared_key.hpp"
#include "socc/channels.hpp"
#include "socc/lcm_url.hpp"
#include "socc/version.hpp"
#include "view_model.hpp"
#include "web_server.hpp"

namespace {

struct Options {
  std::string lcm_url{socc::channels::kDefaultLcmUrl};
  std::string bind = "127.0.0.1";
  int port = 8765;
  std::string key_file;
  std::string web_root;
  int max_clients = 8;
  std::string url_file;
};

bool isLoopback(const std::string& address) {
  return address == "127.0.0.1" || address == "localhost" || address.rfind("127.", 0) == 0;
}

// The page next to the binary (build tree: build/tools/view/web) or installed (share/socc/view).
std::string defaultWebRoot(const char* argv0) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  const fs::path dir = ec ? fs::path(argv0).parent_path() : exe.parent_path();
  for (const fs::path& candidate : {dir / "view" / "web", dir / ".." / "share" / "socc" / "view"})
    if (fs::exists(candidate / "index.html")) return candidate.string();
  return (dir / "view" / "web").string();
}

int run(const Options& options) {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);  // before any thread starts

  if (const std::string why =
          socc::checkLcmUrl(options.lcm_url, socc::lcmAuthFor(options.key_file));
      !why.empty()) {
    std::cerr << "socc-view: " << why << '\n';
    return 2;
  }
  socc::view::WebServerOptions web;
  web.bind = options.bind;
  web.port = options.port;
  web.web_root = options.web_root;
  web.max_clients = options.max_clients;
  if (!isLoopback(options.bind)) {
    if (options.key_file.empty()) {
      std::cerr << "socc-view: --bind " << options.bind
                << " is not loopback: LAN access needs --key-file (the map service's key, "
                   "docs/security.md)\n";
      return 2;
    }
  }
  if (!options.key_file.empty()) {
    try {
      web.token = socc::view::accessToken(socc::auth::SharedKey::fromFile(options.key_file));
    } catch (const std::exception& e) {
      std::cerr << "socc-view: " << e.what() << '\n';
      return 2;
    }
  }
  socc::view::ViewModel model;
  std::unique_ptr<socc::view::LcmFeed> feed;
  std::unique_ptr<socc::view::WebServer> server;
  try {
    feed = std::make_unique<socc::view::LcmFeed>(options.lcm_url, model);
    web.metrics = [&model, feed = feed.get()] {
      return model.read([feed](const socc::view::ViewModel& m) {
        return "\"delta_bytes\":" + std::to_string(feed->deltaBytes()) +
               ",\"status_bytes\":" + std::to_string(feed->statusBytes()) +
               ",\"integrate_bytes\":" + std::to_string(feed->integrateBytes()) +
               ",\"lcm_dropped\":" + std::to_string(feed->dropped()) +
               ",\"deltas\":" + std::to_string(m.deltasReceived()) +
               ",\"voxels\":" + std::to_string(m.voxelCount()) +
               ",\"blocks\":" + std::to_string(m.blocks().size()) +
               ",\"robots\":" + std::to_string(m.robots().size());
      });
    };
    server = std::make_unique<socc::view::WebServer>(web, model);
  } catch (const std::exception& e) {
    std::cerr << "socc-view: " << e.what() << '\n';
    return 1;
  }
  const std::string host = options.bind == "0.0.0.0" ? "127.0.0.1" : options.bind;
  const std::string query = web.token.empty() ? "" : "?token=" + web.token;
  const std::string url = "http://" + host + ":" + std::to_string(server->port()) + "/" + query;
  std::cout << "socc-view: " << url << "\nsocc-view: Foxglove: ws://" << host << ':'
            << server->port() << "/foxglove" << query << std::endl;
  if (!options.url_file.empty()) std::ofstream(options.url_file) << url << '\n';
  int signal = 0;
  sigwait(&stop_signals, &signal);
  server.reset();  // sessions first: they read the model
  feed.reset();
  std::cerr << "socc-view: stopped\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "socc-view: live view of the shared map in a browser (three.js page) and in Foxglove.\n"
      "Listens to SOCC/MAP_DELTA (map_server --view-period), SOCC/STATUS and the robots'\n"
      "INTEGRATE requests; serves http://<bind>:<port>/ and ws://<bind>:<port>/foxglove.\n"
      "Binds to 127.0.0.1; another address needs --key-file (docs/view.md)."};
  app.set_version_flag("--version", socc::versionLine("socc-view"));
  Options options;
  options.web_root = defaultWebRoot(argv[0]);
  app.add_option("--lcm-url", options.lcm_url, "LCM URL of the map server's group")
      ->capture_default_str();
  app.add_option("--bind", options.bind,
                 "address to listen on; other than loopback needs --key-file")
      ->capture_default_str();
  app.add_option("--port", options.port, "HTTP/WebSocket port (0: any free port)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  app.add_option("--key-file", options.key_file,
                 "the map service's shared key (docs/security.md): clients must present the "
                 "access token derived from it (?token=..., printed at start)");
  app.add_option("--web-root", options.web_root, "directory of the page's files")
      ->capture_default_str();
  app.add_option("--max-clients", options.max_clients, "WebSocket clients at once")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--url-file", options.url_file, "also write the page's URL to this file");
  CLI11_PARSE(app, argc, argv);
  return run(options);
}
