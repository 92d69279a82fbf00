#ifndef FITBASE_SERVICES_HTTP_HTTP_SERVER_H_
#define FITBASE_SERVICES_HTTP_HTTP_SERVER_H_

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "grpcpp/channel.h"

namespace httplib {
class Server;
}

namespace fitbase::http {

struct HttpServerOptions {
  std::string listen = "127.0.0.1:7403";  // host:port; port 0 picks a free one.
  // The page: index.html and its modules; node_modules/three under it serves as /vendor/three.
  std::filesystem::path web_root = "web";
  // The fit service, normally FitServer::InProcessChannel().
  std::shared_ptr<grpc::Channel> channel;
  // Request bodies above this are refused with 413 before they are read whole: an hm08 OBJ
  // is about 1.5 MB, an .fba avatar 160 KB.
  size_t max_body_bytes = size_t{8} << 20;
  // Both or neither: HTTPS with this PEM certificate chain and key.
  std::filesystem::path tls_cert;
  std::filesystem::path tls_key;
  int threads = 8;
};

// The shopper's page and its JSON API (docs/http-api.md) over cpp-httplib. Every API handler
// calls fitbase.v1.FitService through `channel` with the caller's X-Api-Key, so keys, tenants,
// limits and errors are the fit service's own; this layer only translates JSON and status
// codes, and parses uploads.
class HttpServer {
 public:
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(HttpServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }
  // Stops accepting, finishes the requests in flight, and joins the listener.
  void Shutdown();

 private:
  HttpServer() = default;

  HttpServerOptions options_;
  std::unique_ptr<httplib::Server> server_;
  std::thread listener_;
  int port_ = 0;
};

}  // namespace fitbase::http

#endif  // FITBASE_SERVICES_HTTP_HTTP_SERVER_H_
