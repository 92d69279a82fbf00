#ifndef FITBASE_SERVICES_BUILD_COORDINATOR_SERVER_H_
#define FITBASE_SERVICES_BUILD_COORDINATOR_SERVER_H_

#include <filesystem>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "body/body_model.h"
#include "grpcpp/grpcpp.h"
#include "services/build/catalog_service.h"
#include "services/build/coordinator.h"
#include "services/build/coordinator_service.h"
#include "services/rpc/api_keys.h"
#include "services/rpc/periodic_thread.h"
#include "storage/asset_store.h"

namespace fitbase::build {

struct CoordinatorServerOptions {
  std::filesystem::path db;     // The RocksDB store; created when missing.
  std::string listen = "127.0.0.1:7401";  // Port 0 picks a free one (see port()).
  std::filesystem::path data_dir;          // MakeHuman data, for garment imports.
  rpc::ApiKeyRegistry keys;
  CoordinatorOptions coordinator;
  // Largest request or response, each way; larger ones fail with RESOURCE_EXHAUSTED.
  int max_message_bytes = 64 << 20;
  absl::Duration reap_period = absl::Seconds(1);
  // Null: plaintext. TlsServerCredentials with a CA: mutual TLS, only certified workers.
  std::shared_ptr<grpc::ServerCredentials> credentials;
  // Where large values go: see storage::OpenOptions::blob_files.
  bool blob_files = true;
};

// The coordinator process's gRPC server: Coordinator, WorkerQueue and Catalog over one store,
// plus grpc.health.v1.Health and reflection. Health is NOT_SERVING from the moment the port is
// bound until every build is recovered, and again once a drain begins.
class CoordinatorServer {
 public:
  static absl::StatusOr<std::unique_ptr<CoordinatorServer>> Start(
      CoordinatorServerOptions options);
  ~CoordinatorServer();
  CoordinatorServer(const CoordinatorServer&) = delete;
  CoordinatorServer& operator=(const CoordinatorServer&) = delete;

  int port() const { return port_; }
  Coordinator& coordinator() { return *coordinator_; }
  storage::AssetStore& store() { return *store_; }

  // NOT_SERVING, then stops: calls in flight get `grace` to finish, long-polls end at once.
  void Shutdown(absl::Duration grace);

 private:
  CoordinatorServer() = default;

  CoordinatorServerOptions options_;
  std::unique_ptr<storage::AssetStore> store_;
  std::unique_ptr<body::BodyModel> model_;
  CoordinatorSlot slot_;
  std::unique_ptr<CoordinatorService> coordinator_service_;
  std::unique_ptr<WorkerQueueService> worker_queue_service_;
  std::unique_ptr<CatalogService> catalog_service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<Coordinator> coordinator_;
  int port_ = 0;
  bool stopped_ = false;
  std::unique_ptr<rpc::PeriodicThread> reaper_;
};

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_COORDINATOR_SERVER_H_
