#ifndef FITBASE_SERVICES_FIT_FIT_SERVICE_H_
#define FITBASE_SERVICES_FIT_FIT_SERVICE_H_

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "fitbase/v1/fit_service.grpc.pb.h"
#include "pipeline/avatar_from_measurements.h"
#include "services/fit/call_queue.h"
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
  // Calls admitted at once, running or waiting for a fit thread; more are RESOURCE_EXHAUSTED
  // at once. A served call waits behind at most this many, so the bound caps its latency past
  // saturation: 16 calls of ~0.15 ms on 2 threads queue for ~1 ms, and 16 clients already keep
  // 2 cores busy without one refusal, where a limit of 8 refused 1-2% (README, "Overload").
  // 0: 8 per fit thread.
  int max_calls_in_flight = 0;
  int threads = 0;  // Fit threads; 0: one per core.
  // Tests only: runs on the fit thread before each admitted call's work (to hold calls).
  std::function<void()> before_call;
};

// fitbase.v1.FitService on the callback API, for customer and admin keys of the garment's
// tenant. gRPC's threads only admit a call (CallQueue: at most max_calls_in_flight, the rest
// RESOURCE_EXHAUSTED at once); the fit threads do the work (a fit of well under a
// millisecond). Calls past their deadline or cancelled stop before each fit.
// AvatarFromMeasurements holds a fit thread for ~25 ms, about a second more the first time a
// basis is used; rare enough (once per customer) not to need threads of its own.
class FitService final : public v1::FitService::CallbackService {
 public:
  FitService(FitCatalog* catalog, const rpc::ApiKeyRegistry* keys,
             const FitServiceOptions& options);

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
  // Fits every size asked for, measures each against the body of the weights and judges it:
  // about 0.1 s of a fit thread for four sizes of an 8k-vertex garment, once per customer
  // and garment.
  grpc::ServerUnaryReactor* AdviseSize(grpc::CallbackServerContext* context,
                                       const v1::AdviseSizeRequest* request,
                                       v1::SizeAdvice* response) override;
  grpc::ServerUnaryReactor* ListShopGarments(grpc::CallbackServerContext* context,
                                         const v1::ListShopGarmentsRequest* request,
                                         v1::ShopGarments* response) override;
  grpc::ServerUnaryReactor* GetBodyTopology(grpc::CallbackServerContext* context,
                                            const v1::GetBodyTopologyRequest* request,
                                            v1::BodyTopology* response) override;

 private:
  // The basis's measurement model, built on first use. Builds are serialised so that a burst
  // of first calls builds it once instead of once per call.
  absl::StatusOr<std::shared_ptr<const pipeline::MeasurementModel>> MeasurementModelFor(
      const pipeline::LoadedAvatarBasis& basis);
  // Runs `work` on a fit thread and answers its status, or refuses the call when
  // max_calls_in_flight are admitted.
  grpc::ServerUnaryReactor* Admit(grpc::CallbackServerContext* context,
                                  std::function<absl::Status()> work);

  FitCatalog* catalog_;
  const rpc::ApiKeyRegistry* keys_;
  const FitServiceOptions options_;
  std::mutex build_mutex_;  // Held while a model is built; taken before models_mutex_.
  std::mutex models_mutex_;
  // By avatar basis id (the basis's content hash, so an entry never goes stale).
  std::map<std::string, std::shared_ptr<const pipeline::MeasurementModel>> models_;
  // Last: destroyed first, running what it has queued while the members above still exist.
  CallQueue calls_;
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_FIT_SERVICE_H_
