#include "services/build/coordinator_server.h"

#include "absl/strings/str_cat.h"
#include "core/log_line.h"
#include "core/status_macros.h"
#include "grpcpp/ext/proto_server_reflection_plugin.h"
#include "grpcpp/health_check_service_interface.h"
#include "services/rpc/channel.h"

namespace fitbase::build {

absl::StatusOr<std::unique_ptr<CoordinatorServer>> CoordinatorServer::Start(
    CoordinatorServerOptions options) {
  std::unique_ptr<CoordinatorServer> server(new CoordinatorServer());
  server->options_ = std::move(options);
  const CoordinatorServerOptions& o = server->options_;
  ASSIGN_OR_RETURN(server->store_,
                   storage::AssetStore::Open(o.db, {.mode = storage::OpenMode::kPrimary,
                                                    .secondary_path = {},
                                                    .max_value_bytes = size_t{256} << 20,
                                                    .blob_files = o.blob_files,
                                                    .min_blob_bytes = 4096}));
  ASSIGN_OR_RETURN(body::BodyModel model, body::BodyModel::Load(o.data_dir));
  server->model_ = std::make_unique<body::BodyModel>(std::move(model));
  server->coordinator_service_ = std::make_unique<CoordinatorService>(&server->slot_, &o.keys);
  server->worker_queue_service_ = std::make_unique<WorkerQueueService>(&server->slot_, &o.keys);
  // Beside the store, never inside it: "store/" names the same folder as "store".
  std::filesystem::path db = o.db.lexically_normal();
  if (!db.has_filename()) db = db.parent_path();
  server->catalog_service_ = std::make_unique<CatalogService>(
      server->store_.get(), server->model_.get(), &o.keys,
      db.parent_path() / (db.filename().string() + "-checkpoints"));

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(rpc::ListenAddress(o.listen),
                           o.credentials ? o.credentials : grpc::InsecureServerCredentials(),
                           &server->port_);
  builder.SetMaxReceiveMessageSize(o.max_message_bytes);
  builder.SetMaxSendMessageSize(o.max_message_bytes);
  builder.RegisterService(server->coordinator_service_.get());
  builder.RegisterService(server->worker_queue_service_.get());
  builder.RegisterService(server->catalog_service_.get());
  server->server_ = builder.BuildAndStart();
  if (server->server_ == nullptr || server->port_ == 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen on ", o.listen));
  }
  grpc::HealthCheckServiceInterface* health = server->server_->GetHealthCheckService();
  health->SetServingStatus(false);
  const absl::Time start = absl::Now();
  ASSIGN_OR_RETURN(server->coordinator_,
                   Coordinator::Open(server->store_.get(), o.coordinator));
  server->slot_.Set(server->coordinator_.get());
  health->SetServingStatus(true);
  core::LogLine("coordinator_serving")
      .Add("port", server->port_)
      .Add("db", o.db.string())
      .Add("recovery_seconds", absl::ToDoubleSeconds(absl::Now() - start));
  server->reaper_ = std::make_unique<rpc::PeriodicThread>(
      o.reap_period, [c = server->coordinator_.get()] { c->ReapExpiredLeases(); });
  return server;
}

void CoordinatorServer::Shutdown(absl::Duration grace) {
  if (stopped_) return;
  stopped_ = true;
  if (reaper_ != nullptr) reaper_->Stop();
  if (server_ != nullptr) {
    server_->GetHealthCheckService()->SetServingStatus(false);
    // Long-polls and watches return as soon as the coordinator shuts down, so the server's
    // drain waits only for short calls.
    if (coordinator_ != nullptr) coordinator_->Shutdown();
    server_->Shutdown(absl::ToChronoTime(absl::Now() + grace));
  }
  if (server_ != nullptr) core::LogLine("coordinator_stopped").Add("port", port_);
}

CoordinatorServer::~CoordinatorServer() { Shutdown(absl::Seconds(5)); }

}  // namespace fitbase::build
