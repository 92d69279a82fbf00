#ifndef FITBASE_SERVICES_BUILD_CATALOG_SERVICE_H_
#define FITBASE_SERVICES_BUILD_CATALOG_SERVICE_H_

#include <filesystem>

#include "body/body_model.h"
#include "fitbase/v1/catalog.grpc.pb.h"
#include "services/rpc/api_keys.h"
#include "storage/asset_store.h"

namespace fitbase::build {

// fitbase.v1.Catalog: a tenant's garments and avatar bases, written through the coordinator's
// store (it is the store's only writer). Ingestion and admin keys write and read; the tenant is
// the key's, so another tenant's garment is NOT_FOUND. Imports run the CLI's code.
class CatalogService final : public v1::Catalog::Service {
 public:
  // `model`: the MakeHuman body model that garments are bound to and populations sampled from.
  // `checkpoint_root`: where CreateCheckpoint writes (on the store's file system).
  CatalogService(storage::AssetStore* store, const body::BodyModel* model,
                 const rpc::ApiKeyRegistry* keys, std::filesystem::path checkpoint_root)
      : store_(store), model_(model), keys_(keys), checkpoint_root_(std::move(checkpoint_root)) {}

  grpc::Status UploadGarment(grpc::ServerContext* context,
                             const v1::UploadGarmentRequest* request,
                             v1::UploadGarmentResponse* response) override;
  grpc::Status ListGarments(grpc::ServerContext* context, const v1::ListGarmentsRequest* request,
                            v1::ListGarmentsResponse* response) override;
  grpc::Status PublishAvatarBasis(grpc::ServerContext* context,
                                  const v1::PublishAvatarBasisRequest* request,
                                  v1::PublishAvatarBasisResponse* response) override;
  grpc::Status GetAvatarBasis(grpc::ServerContext* context,
                              const v1::GetAvatarBasisRequest* request,
                              v1::AvatarBasis* response) override;
  grpc::Status CreateCheckpoint(grpc::ServerContext* context,
                                const v1::CreateCheckpointRequest* request,
                                v1::CreateCheckpointResponse* response) override;

 private:
  storage::AssetStore* store_;
  const body::BodyModel* model_;
  const rpc::ApiKeyRegistry* keys_;
  const std::filesystem::path checkpoint_root_;
};

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_CATALOG_SERVICE_H_
