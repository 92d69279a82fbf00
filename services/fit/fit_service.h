#ifndef FITBASE_SERVICES_FIT_FIT_SERVICE_H_
#define FITBASE_SERVICES_FIT_FIT_SERVICE_H_

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "fitbase/v1/fit_service.grpc.pb.h"
#include "pipeline/avatar_from_measurements.h"
#include "services/fit/fit_catalog.h"
#include "services/rpc/api_keys.h"

namespace fitbase::fit {

struct FitServiceOptions {
  // Largest outfit per call: each item is a fit and a response of up to a few hundred KB.
  int max_outfit_items = 64;
  // A projection is flagged out of distribution when its mean reconstruction error exceeds
  // this many times the basis's training error, or a weight lies beyond this many sigma.
  double ood_error_ratio = 3.0;
  double ood_sigmas = 4.0;
  // Measurement models kept, one per avatar basis: a few hundred KB each, a second to build.
  int max_measurement_models = 16;
};

// fitbase.v1.FitService on the callback API: every call is answered on gRPC's own threads
// without blocking (the work is a fit of well under a millisecond), for customer and admin
// keys of the garment's tenant. Calls past their deadline or cancelled stop before each fit.
// AvatarFromMeasurements is the exception: ~25 ms of solving on that thread, and about a
// second more the first time a basis is used; rare enough (once per customer) not to need a
// pool of its own.
class FitService final : public v1::FitService::CallbackService {
 public:
  FitService(FitCatalog* catalog, const rpc::ApiKeyRegistry* keys, const FitServiceOptions& options)
      : catalog_(catalog), keys_(keys), options_(options) {}

  grpc::ServerUnaryReactor* ProjectAvatar(grpc::CallbackServerContext* context,
                                          const v1::ProjectAvatarRequest* request,
                                          v1::AvatarProjection* response) override;
  grpc::ServerUnaryReactor* FitGarment(grpc::CallbackServerContext* context,
                                       const v1::FitGarmentRequest* request,
                                       v1::FittedGarment* response) override;
  grpc::ServerUnaryReactor* FitOutfit(grpc::CallbackServerContext* context,
                                      const v1::FitOutfitRequest* request,
                                      v1::FitOutfitResponse* response) override;
  grpc::ServerUnaryReactor* GetGarmentTopology(grpc::CallbackServerContext* context,
                                               const v1::GetGarmentTopologyRequest* request,
                                               v1::GarmentTopology* response) override;
  grpc::ServerUnaryReactor* AvatarFromMeasurements(
      grpc::CallbackServerContext* context, const v1::AvatarFromMeasurementsRequest* request,
      v1::AvatarFromMeasurementsResponse* response) override;

 private:
  // The basis's measurement model, built on first use. Builds are serialised so that a burst
  // of first calls builds it once instead of once per call.
  absl::StatusOr<std::shared_ptr<const pipeline::MeasurementModel>> MeasurementModelFor(
      const pipeline::LoadedAvatarBasis& basis);

  FitCatalog* catalog_;
  const rpc::ApiKeyRegistry* keys_;
  const FitServiceOptions options_;
  std::mutex build_mutex_;  // Held while a model is built; taken before models_mutex_.
  std::mutex models_mutex_;
  // By avatar basis id (the basis's content hash, so an entry never goes stale).
  std::map<std::string, std::shared_ptr<const pipeline::MeasurementModel>> models_;
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_FIT_SERVICE_H_
