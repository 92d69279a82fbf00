#ifndef FITBASE_SERVICES_FIT_FIT_SERVER_H_
#define FITBASE_SERVICES_FIT_FIT_SERVER_H_

#include <filesystem>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/grpcpp.h"
#include "services/fit/fit_catalog.h"
#include "services/fit/fit_service.h"
#include "services/rpc/api_keys.h"
#include "services/rpc/periodic_thread.h"
#include "storage/asset_store.h"

namespace fitbase::fit {

struct FitServerOptions {
  // The store to read: a live coordinator's in this process (borrowed), else the database at
  // `db`, opened as a secondary of a live coordinator's (created without blob files) or
  // read-only (a checkpoint).
  storage::AssetStore* store = nullptr;
  std::filesystem::path db;
  storage::OpenMode mode = storage::OpenMode::kSecondary;
  std::filesystem::path secondary_path;  // kSecondary: its own folder for RocksDB's logs.
  std::string listen = "127.0.0.1:7402";
  rpc::ApiKeyRegistry keys;
  FitCatalogOptions catalog;
  FitServiceOptions service;
  // Requests and responses above this are RESOURCE_EXHAUSTED: an avatar is 160 KB raw, an
  // outfit of 64 garments of 8k vertices 6 MB raw.
  int max_receive_bytes = 4 << 20;
  int max_send_bytes = 16 << 20;
};

// The fit service's server: FitService, health and reflection. A secondary store catches up
// with its primary every catalog.refresh, so newly published versions serve without a restart.
class FitServer {
 public:
  static absl::StatusOr<std::unique_ptr<FitServer>> Start(FitServerOptions options);
  ~FitServer();
  FitServer(const FitServer&) = delete;
  FitServer& operator=(const FitServer&) = delete;

  int port() const { return port_; }
  FitCatalog& catalog() { return *catalog_; }
  // A channel to this server's services inside the process (the HTTP API's way in): calls
  // pass the same keys, limits and errors as over the network, without a socket.
  std::shared_ptr<grpc::Channel> InProcessChannel();
  void Shutdown(absl::Duration grace);

 private:
  FitServer() = default;

  FitServerOptions options_;
  std::unique_ptr<storage::AssetStore> owned_store_;
  storage::AssetStore* store_ = nullptr;
  std::unique_ptr<FitCatalog> catalog_;
  std::unique_ptr<FitService> service_;
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
  bool stopped_ = false;
  std::unique_ptr<rpc::PeriodicThread> catch_up_;
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_FIT_SERVER_H_
