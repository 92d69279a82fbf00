#include "services/fit/fit_server.h"

#include "absl/strings/str_cat.h"
#include "core/log_line.h"
#include "core/status_macros.h"
#include "grpcpp/ext/proto_server_reflection_plugin.h"
#include "grpcpp/health_check_service_interface.h"
#include "services/rpc/channel.h"

namespace fitbase::fit {

absl::StatusOr<std::unique_ptr<FitServer>> FitServer::Start(FitServerOptions options) {
  std::unique_ptr<FitServer> server(new FitServer());
  server->options_ = std::move(options);
  const FitServerOptions& o = server->options_;
  if (o.store != nullptr) {
    server->store_ = o.store;
  } else {
    if (o.mode == storage::OpenMode::kPrimary) {
      return absl::InvalidArgumentError("the fit service opens the store read-only");
    }
    ASSIGN_OR_RETURN(server->owned_store_,
                     storage::AssetStore::Open(o.db, {.mode = o.mode,
                                                      .secondary_path = o.secondary_path,
                                                      .max_value_bytes = size_t{256} << 20,
                                                      .blob_files = false,
                                                      .min_blob_bytes = 4096}));
    server->store_ = server->owned_store_.get();
  }
  server->catalog_ = std::make_unique<FitCatalog>(server->store_, o.catalog);
  server->service_ = std::make_unique<FitService>(server->catalog_.get(), &o.keys, o.service);

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(rpc::ListenAddress(o.listen), grpc::InsecureServerCredentials(),
                           &server->port_);
  builder.SetMaxReceiveMessageSize(o.max_receive_bytes);
  builder.SetMaxSendMessageSize(o.max_send_bytes);
  builder.RegisterService(server->service_.get());
  server->server_ = builder.BuildAndStart();
  if (server->server_ == nullptr || server->port_ == 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen on ", o.listen));
  }
  server->server_->GetHealthCheckService()->SetServingStatus(true);
  if (server->owned_store_ != nullptr && o.mode == storage::OpenMode::kSecondary) {
    server->catch_up_ =
        std::make_unique<rpc::PeriodicThread>(o.catalog.refresh, [s = server->store_] {
          if (absl::Status status = s->TryCatchUpWithPrimary(); !status.ok()) {
            core::LogLine("catch_up_failed").Add("error", status.ToString());
          }
        });
  }
  core::LogLine("fit_serving").Add("port", server->port_);
  return server;
}

std::shared_ptr<grpc::Channel> FitServer::InProcessChannel() {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(options_.max_send_bytes);
  arguments.SetMaxSendMessageSize(options_.max_receive_bytes);
  return server_->InProcessChannel(arguments);
}

void FitServer::Shutdown(absl::Duration grace) {
  if (stopped_) return;
  stopped_ = true;
  if (catch_up_ != nullptr) catch_up_->Stop();
  if (server_ != nullptr) {
    server_->GetHealthCheckService()->SetServingStatus(false);
    server_->Shutdown(absl::ToChronoTime(absl::Now() + grace));
    core::LogLine("fit_stopped").Add("port", port_);
  }
}

FitServer::~FitServer() { Shutdown(absl::Seconds(2)); }

}  // namespace fitbase::fit
