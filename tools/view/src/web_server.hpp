#pragma once
// socc-view's HTTP side (civetweb): the page's static files (one directory, generated at build
// time), the page's WebSocket /ws and the Foxglove WebSocket /foxglove. Each WebSocket client
// gets its own session (client_session.hpp); at most max_clients at once.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "view_model.hpp"

struct mg_context;
struct mg_connection;

namespace socc::view {

struct WebServerOptions {
  std::string bind = "127.0.0.1";
  int port = 8765;  // 0: any free port
  std::string web_root;
  std::string token;  // empty: no token needed (localhost)
  int max_clients = 8;
  /// Extra fields of GET /metrics.json (a JSON object's members, without braces), e.g. the LCM
  /// side's counters; the server adds its own (clients, bytes_sent).
  std::function<std::string()> metrics;
};

class WebServer {
 public:
  /// Throws std::runtime_error when the port cannot be bound or web_root has no index.html.
  WebServer(const WebServerOptions& options, ViewModel& model);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const { return port_; }
  int clients() const { return clients_; }
  /// WebSocket payload bytes written to all clients since the start.
  std::uint64_t bytesSent() const { return bytes_sent_; }

 private:
  static int authorize(mg_connection* conn, void* self);
  static int serveMetrics(mg_connection* conn, void* self);
  static int connect(const mg_connection* conn, void* self);
  static void ready(mg_connection* conn, void* self);
  static int data(mg_connection* conn, int flags, char* data, std::size_t size, void* self);
  static void close(const mg_connection* conn, void* self);
  bool tokenOk(const mg_connection* conn) const;

  WebServerOptions options_;
  ViewModel& model_;
  mg_context* context_ = nullptr;
  int port_ = 0;
  std::atomic<int> clients_{0};
  std::atomic<std::uint64_t> next_session_{1};
  std::atomic<std::uint64_t> bytes_sent_{0};
};

}  // namespace socc::view
