#include "services/http/http_server.h"

#include <chrono>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "core/status_macros.h"
#include "google/protobuf/util/json_util.h"
#include "proto/avatar_codec.h"
#include "services/http/http_body.h"
#include "services/rpc/call_auth.h"
// Last: it includes <resolv.h>, whose `_res` macro breaks Eigen's headers included after it.
#include "httplib.h"

namespace fitbase::http {
namespace {

// Fit calls answer in milliseconds; advice in a tenth of a second; a first call on a basis
// builds its measurement model in about a second.
constexpr auto kCallDeadline = std::chrono::seconds(30);

int HttpStatusOf(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return 200;
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::OUT_OF_RANGE:
      return 400;
    case grpc::StatusCode::UNAUTHENTICATED:
      return 401;
    case grpc::StatusCode::PERMISSION_DENIED:
      return 403;
    case grpc::StatusCode::NOT_FOUND:
      return 404;
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::ABORTED:
      return 409;
    case grpc::StatusCode::FAILED_PRECONDITION:
      return 412;
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return 429;
    case grpc::StatusCode::CANCELLED:
      return 499;
    case grpc::StatusCode::UNIMPLEMENTED:
      return 501;
    case grpc::StatusCode::UNAVAILABLE:
      return 503;
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return 504;
    default:
      return 500;
  }
}

std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          absl::StrAppend(&out, "\\u00", absl::Hex(c, absl::kZeroPad2));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

void SendError(httplib::Response& res, int status, const std::string& code,
               const std::string& message) {
  res.status = status;
  res.set_content(absl::StrCat("{\"error\": {\"code\": ", Quoted(code),
                               ", \"message\": ", Quoted(message), "}}\n"),
                  "application/json");
}

void SendGrpcError(httplib::Response& res, const grpc::Status& status) {
  // gRPC's codes are absl's, number for number.
  SendError(res, HttpStatusOf(status.error_code()),
            absl::StatusCodeToString(static_cast<absl::StatusCode>(status.error_code())),
            status.error_message());
}

void SendMessage(httplib::Response& res, const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!status.ok()) {
    SendError(res, 500, "INTERNAL", absl::StrCat("the answer cannot be written as JSON: ",
                                                 status.message().as_string()));
    return;
  }
  res.status = 200;
  res.set_content(json, "application/json");
}

// Parses a JSON request body into `message`; false (and the 400 sent) when it does not parse.
bool ParseBody(const httplib::Request& req, httplib::Response& res,
               google::protobuf::Message* message) {
  const absl::Status status = ParseJsonBody(req.body, message);
  if (!status.ok()) SendError(res, 400, "INVALID_ARGUMENT", std::string(status.message()));
  return status.ok();
}

// The avatar Draco-encoded, as the body of the weights is sent: a page shows and sends back
// the same quantized mesh, so the garment is fitted to what the shopper sees.
absl::StatusOr<v1::Avatar> DracoAvatar(const v1::Avatar& avatar) {
  ASSIGN_OR_RETURN(const core::Positions positions, proto::AvatarPositions(avatar));
  return proto::AvatarFromPositions(positions, /*draco=*/true);
}

std::unique_ptr<grpc::ClientContext> CallFor(const httplib::Request& req) {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() + kCallDeadline);
  rpc::AddApiKey(*context, req.get_header_value("X-Api-Key"));
  return context;
}

void AddRoutes(httplib::Server& server, const HttpServerOptions& options) {
  auto stub = std::shared_ptr<v1::FitService::Stub>(v1::FitService::NewStub(options.channel));

  server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("ok\n", "text/plain");
  });
  server.Get("/api/v1/garments", [stub](const httplib::Request& req, httplib::Response& res) {
    v1::ShopGarments answer;
    const grpc::Status status =
        stub->ListShopGarments(CallFor(req).get(), v1::ListShopGarmentsRequest(), &answer);
    status.ok() ? SendMessage(res, answer) : SendGrpcError(res, status);
  });
  server.Get(R"(/api/v1/garments/([^/]+)/topology)",
             [stub](const httplib::Request& req, httplib::Response& res) {
               v1::GetGarmentTopologyRequest request;
               request.set_garment_id(req.matches[1].str());
               v1::GarmentTopology answer;
               const grpc::Status status =
                   stub->GetGarmentTopology(CallFor(req).get(), request, &answer);
               status.ok() ? SendMessage(res, answer) : SendGrpcError(res, status);
             });
  server.Get("/api/v1/bodies/topology", [stub](const httplib::Request& req,
                                               httplib::Response& res) {
    v1::GetBodyTopologyRequest request;
    request.set_population(req.get_param_value("population"));
    v1::BodyTopology answer;
    const grpc::Status status = stub->GetBodyTopology(CallFor(req).get(), request, &answer);
    status.ok() ? SendMessage(res, answer) : SendGrpcError(res, status);
  });
  server.Post("/api/v1/bodies/project", [stub](const httplib::Request& req,
                                               httplib::Response& res) {
    v1::ProjectAvatarRequest request;
    request.set_population(req.get_param_value("population"));
    // body=own answers the upload itself as the body, to be shown and sent back with the fit
    // (POST /api/v1/fit's body); weights, the default, the body of the weights.
    const std::string body = req.has_param("body") ? req.get_param_value("body") : "weights";
    if (body != "own" && body != "weights") {
      SendError(res, 400, "INVALID_ARGUMENT",
                absl::StrCat("body is '", body, "'; it is own or weights"));
      return;
    }
    request.set_with_body(body == "weights");
    absl::StatusOr<v1::Avatar> avatar =
        ParseUploadedAvatar(req.body, req.get_header_value("Content-Type"));
    if (!avatar.ok()) {
      SendError(res, 400, "INVALID_ARGUMENT", std::string(avatar.status().message()));
      return;
    }
    *request.mutable_avatar() = *std::move(avatar);
    v1::AvatarProjection answer;
    const grpc::Status status = stub->ProjectAvatar(CallFor(req).get(), request, &answer);
    if (!status.ok()) return SendGrpcError(res, status);
    if (body == "own") {
      absl::StatusOr<v1::Avatar> own = DracoAvatar(request.avatar());
      if (!own.ok()) {
        SendError(res, 400, "INVALID_ARGUMENT", std::string(own.status().message()));
        return;
      }
      *answer.mutable_body() = *std::move(own);
    }
    SendMessage(res, answer);
  });
  server.Post("/api/v1/bodies/from-measurements", [stub](const httplib::Request& req,
                                                         httplib::Response& res) {
    v1::AvatarFromMeasurementsRequest request;
    if (!ParseBody(req, res, &request)) return;
    v1::AvatarFromMeasurementsResponse answer;
    const grpc::Status status =
        stub->AvatarFromMeasurements(CallFor(req).get(), request, &answer);
    status.ok() ? SendMessage(res, answer) : SendGrpcError(res, status);
  });
  server.Post("/api/v1/fit", [stub](const httplib::Request& req, httplib::Response& res) {
    v1::TryOnRequest request;
    if (!ParseBody(req, res, &request)) return;
    v1::TryOnResponse answer;
    v1::FitOutfitRequest outfit;
    *outfit.mutable_weights() = request.weights();
    if (request.has_body()) *outfit.mutable_body() = request.body();
    v1::OutfitItem* item = outfit.add_items();
    item->set_garment_id(request.garment_id());
    item->set_method(request.method());
    grpc::Status status = stub->FitOutfit(CallFor(req).get(), outfit, answer.mutable_outfit());
    if (!status.ok()) return SendGrpcError(res, status);
    v1::AdviseSizeRequest advise;
    *advise.mutable_weights() = request.weights();
    advise.set_garment_id(request.garment_id());
    advise.set_method(request.method());
    status = stub->AdviseSize(CallFor(req).get(), advise, answer.mutable_advice());
    status.ok() ? SendMessage(res, answer) : SendGrpcError(res, status);
  });
}

}  // namespace

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(HttpServerOptions options) {
  if (options.channel == nullptr) return absl::InvalidArgumentError("the HTTP API needs a channel");
  if (options.tls_cert.empty() != options.tls_key.empty()) {
    return absl::InvalidArgumentError("HTTPS needs both a certificate and a key");
  }
  const size_t colon = options.listen.rfind(':');
  int port = 0;
  if (colon == std::string::npos ||
      !absl::SimpleAtoi(options.listen.substr(colon + 1), &port) || port < 0 || port > 65535) {
    return absl::InvalidArgumentError(
        absl::StrCat("--http-listen '", options.listen, "' is not host:port"));
  }
  const std::string host = options.listen.substr(0, colon);
  if (!std::filesystem::is_regular_file(options.web_root / "index.html")) {
    return absl::NotFoundError(absl::StrCat("the page's folder ", options.web_root.string(),
                                            " has no index.html"));
  }
  std::unique_ptr<HttpServer> server(new HttpServer());
  if (options.tls_cert.empty()) {
    server->server_ = std::make_unique<httplib::Server>();
  } else {
    auto https = std::make_unique<httplib::SSLServer>(options.tls_cert.c_str(),
                                                      options.tls_key.c_str());
    if (!https->is_valid()) {
      return absl::InvalidArgumentError(absl::StrCat("HTTPS cannot start with certificate ",
                                                     options.tls_cert.string(), " and key ",
                                                     options.tls_key.string()));
    }
    server->server_ = std::move(https);
  }
  httplib::Server& http = *server->server_;
  const int threads = std::max(1, options.threads);
  http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http.set_payload_max_length(options.max_body_bytes);
  http.set_file_extension_and_mimetype_mapping("js", "text/javascript");
  http.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
  http.set_file_extension_and_mimetype_mapping("wasm", "application/wasm");
  const size_t max_body = options.max_body_bytes;
  // Errors cpp-httplib answers itself (no route, a body too large) get the API's JSON shape;
  // it calls this for the handlers' own errors too, which already have their body.
  http.set_error_handler([max_body](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 413) {
      SendError(res, 413, "RESOURCE_EXHAUSTED",
                absl::StrCat("the request body is larger than the limit of ", max_body >> 20,
                             " MiB"));
    } else if (res.status == 404) {
      SendError(res, 404, "NOT_FOUND", absl::StrCat("no such page or endpoint: ", req.path));
    } else {
      SendError(res, res.status, "UNKNOWN", absl::StrCat("HTTP ", res.status));
    }
  });
  http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        SendError(res, 500, "INTERNAL", "the server failed on this request");
      });
  // Vendored modules never change under a URL; the page's own files are revalidated.
  if (!http.set_mount_point("/vendor/three", (options.web_root / "node_modules/three").string(),
                            {{"Cache-Control", "max-age=86400"}})) {
    return absl::NotFoundError(absl::StrCat(
        "three.js is not installed under ", options.web_root.string(),
        "/node_modules (scripts/setup.sh runs `npm ci` there)"));
  }
  http.set_mount_point("/", options.web_root.string(), {{"Cache-Control", "no-cache"}});
  AddRoutes(http, options);

  const int bound = port == 0 ? http.bind_to_any_port(host) : (http.bind_to_port(host, port) ? port : -1);
  if (bound < 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen on ", options.listen));
  }
  server->port_ = bound;
  server->options_ = std::move(options);
  server->listener_ = std::thread([raw = server->server_.get()] { raw->listen_after_bind(); });
  return server;
}

void HttpServer::Shutdown() {
  if (server_ != nullptr) server_->stop();
  if (listener_.joinable()) listener_.join();
}

HttpServer::~HttpServer() { Shutdown(); }

}  // namespace fitbase::http
