#include "web_server.hpp"

#include <civetweb.h>

#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "access_token.hpp"
#include "foxglove_protocol.hpp"
#include "foxglove_session.hpp"
#include "page_session.hpp"

namespace socc::view {
namespace {

const char* kFoxgloveProtocols[] = {foxglove::kSubprotocol};
mg_websocket_subprotocols foxgloveSubprotocols{1, kFoxgloveProtocols};

bool isFoxglove(const mg_connection* conn) {
  const mg_request_info* info = mg_get_request_info(conn);
  return std::strncmp(info->local_uri, "/foxglove", 9) == 0;
}

FrameWriter writerFor(mg_connection* conn, std::atomic<std::uint64_t>& bytes_sent) {
  return [conn, &bytes_sent](bool binary, const void* data, std::size_t size) {
    const int opcode = binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT;
    if (mg_websocket_write(conn, opcode, static_cast<const char*>(data), size) <= 0) return false;
    bytes_sent += size;
    return true;
  };
}

}  // namespace

WebServer::WebServer(const WebServerOptions& options, ViewModel& model)
    : options_(options), model_(model) {
  if (!std::filesystem::exists(std::filesystem::path(options.web_root) / "index.html"))
    throw std::runtime_error("no index.html in " + options.web_root +
                             " (the page is generated at build time: SOCC_BUILD_VIEW)");
  mg_init_library(MG_FEATURES_WEBSOCKET);
  const std::string ports = options.bind + ":" + std::to_string(options.port);
  // Each WebSocket client holds one worker thread while connected, plus room for page loads.
  const std::string threads = std::to_string(options.max_clients + 4);
  const char* config[] = {"listening_ports",
                          ports.c_str(),
                          "document_root",
                          options.web_root.c_str(),
                          "num_threads",
                          threads.c_str(),
                          "enable_directory_listing",
                          "no",
                          "websocket_timeout_ms",
                          "3600000",
                          nullptr};
  mg_callbacks callbacks{};
  context_ = mg_start(&callbacks, this, config);
  if (context_ == nullptr)
    throw std::runtime_error("cannot listen on " + ports + " (port in use?)");
  mg_set_auth_handler(context_, "/", &WebServer::authorize, this);
  mg_set_request_handler(context_, "/metrics.json", &WebServer::serveMetrics, this);
  mg_set_websocket_handler(context_, "/ws", &WebServer::connect, &WebServer::ready,
                           &WebServer::data, &WebServer::close, this);
  mg_set_websocket_handler_with_subprotocols(context_, "/foxglove", &foxgloveSubprotocols,
                                             &WebServer::connect, &WebServer::ready,
                                             &WebServer::data, &WebServer::close, this);
  mg_server_port bound[4]{};
  const int n = mg_get_server_ports(context_, 4, bound);
  port_ = n > 0 ? bound[0].port : options.port;
}

WebServer::~WebServer() {
  if (context_ != nullptr) mg_stop(context_);  // closes every connection (close handlers run)
  mg_exit_library();
}

bool WebServer::tokenOk(const mg_connection* conn) const {
  if (options_.token.empty()) return true;
  const mg_request_info* info = mg_get_request_info(conn);
  if (info->query_string == nullptr) return false;
  char presented[128] = {};
  if (mg_get_var(info->query_string, std::strlen(info->query_string), "token", presented,
                 sizeof(presented)) <= 0)
    return false;
  return tokenMatches(options_.token, presented);
}

int WebServer::authorize(mg_connection* conn, void* self) {
  if (static_cast<WebServer*>(self)->tokenOk(conn)) return 1;
  mg_send_http_error(conn, 403, "socc-view: add ?token=<access token> (socc-view prints it)");
  return 0;
}

int WebServer::serveMetrics(mg_connection* conn, void* self) {
  auto* server = static_cast<WebServer*>(self);
  std::string body = "{\"clients\":" + std::to_string(server->clients_) +
                     ",\"bytes_sent\":" + std::to_string(server->bytes_sent_);
  if (server->options_.metrics) body += "," + server->options_.metrics();
  body += "}\n";
  mg_send_http_ok(conn, "application/json", static_cast<long long>(body.size()));
  mg_write(conn, body.data(), body.size());
  return 200;
}

int WebServer::connect(const mg_connection* conn, void* self) {
  auto* server = static_cast<WebServer*>(self);
  if (!server->tokenOk(conn)) return 1;  // refused
  if (server->clients_ >= server->options_.max_clients) return 1;
  ++server->clients_;
  return 0;
}

void WebServer::ready(mg_connection* conn, void* self) {
  auto* server = static_cast<WebServer*>(self);
  std::unique_ptr<ClientSession> session;
  if (isFoxglove(conn))
    session =
        std::make_unique<FoxgloveSession>(server->model_, writerFor(conn, server->bytes_sent_),
                                          std::to_string(server->next_session_++));
  else
    session = std::make_unique<PageSession>(server->model_, writerFor(conn, server->bytes_sent_));
  session->start();
  mg_set_user_connection_data(conn, session.release());
}

int WebServer::data(mg_connection* conn, int flags, char* data, std::size_t size, void* /*self*/) {
  const int opcode = flags & 0x0f;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  auto* session = static_cast<ClientSession*>(mg_get_user_connection_data(conn));
  if (session != nullptr && opcode == MG_WEBSOCKET_OPCODE_TEXT)
    session->received(std::string(data, size));
  return 1;
}

void WebServer::close(const mg_connection* conn, void* self) {
  auto* server = static_cast<WebServer*>(self);
  // The session's thread may still write to conn: stopped and joined before civetweb frees it.
  auto* session = static_cast<ClientSession*>(mg_get_user_connection_data(conn));
  if (session != nullptr) session->stop();
  delete session;
  --server->clients_;
}

}  // namespace socc::view
