#include "services/fit/fit_service.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <span>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/time/clock.h"
#include "body/body_measurements.h"
#include "clothing/clothing_model.h"
#include "clothing/size_advice.h"
#include "core/pca_basis.h"
#include "proto/mesh_codec.h"
#include "core/status_macros.h"
#include "proto/avatar_codec.h"
#include "proto/draco_codec.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::fit {
namespace {

absl::StatusOr<rpc::Principal> AdmitCustomer(const grpc::CallbackServerContext& context,
                                        const rpc::ApiKeyRegistry& keys) {
  ASSIGN_OR_RETURN(rpc::Principal principal, rpc::AuthenticateCall(context, keys));
  RETURN_IF_ERROR(rpc::RequireRole(principal, {rpc::Role::kCustomer}, "fit garments"));
  return principal;
}

absl::Status CheckAlive(const grpc::CallbackServerContext& context) {
  if (context.IsCancelled()) return absl::CancelledError("the call was cancelled");
  if (absl::Now() > absl::FromChrono(context.deadline())) {
    return absl::DeadlineExceededError("the call's deadline passed");
  }
  return absl::OkStatus();
}

// What a request that names no method is fitted with: the most accurate one built, kernel,
// else linear (catalogues built before kernel).
constexpr const char* kDefaultMethods[] = {"kernel", "linear"};

// One garment size fitted to the weights; its positions (3V, xyz interleaved, m) go to the
// caller's buffer, which a hot path keeps per thread so that a fit allocates nothing.
struct SizeFitted {
  std::shared_ptr<const ServedClothing> clothing;
  std::string method;
  int64_t pushed = 0;
  absl::Duration compute;
};

// own_body: the customer's own mesh (3B floats, m, checked by OwnBody), or empty for the body
// of the weights.
absl::StatusOr<SizeFitted> FitPositions(FitCatalog& catalog, absl::string_view tenant,
                                        const v1::AvatarWeights& weights,
                                        const ServedGarment& garment,
                                        absl::string_view garment_id, absl::string_view size,
                                        absl::string_view method_name, bool cleanup,
                                        std::span<const float> own_body,
                                        Eigen::VectorXf& positions) {
  SizeFitted out;
  if (!method_name.empty()) RETURN_IF_ERROR(clothing::ParseClothingMethod(method_name).status());
  const auto& sizes = garment.topology.sizes();
  if (std::find(sizes.begin(), sizes.end(), size) == sizes.end()) {
    return absl::NotFoundError(absl::StrCat("garment ", garment_id, " has no size '", size,
                                            "'; it has ", absl::StrJoin(sizes, ",")));
  }
  const std::vector<std::string> methods =
      method_name.empty() ? std::vector<std::string>(std::begin(kDefaultMethods),
                                                     std::end(kDefaultMethods))
                          : std::vector<std::string>{std::string(method_name)};
  absl::StatusOr<std::shared_ptr<const ServedClothing>> found;
  for (const std::string& method : methods) {
    out.method = method;
    found = catalog.Clothing({std::string(tenant), std::string(garment_id), std::string(size),
                              garment.avatar_basis_id, method});
    if (!absl::IsNotFound(found.status())) break;
  }
  if (absl::IsNotFound(found.status())) {
    return absl::NotFoundError(absl::StrCat("garment ", garment_id, " size ", size,
                                            " has no published ", absl::StrJoin(methods, " or "),
                                            " clothing basis; build it first"));
  }
  if (!found.ok()) return found.status();
  out.clothing = *std::move(found);
  ASSIGN_OR_RETURN(const Eigen::VectorXd checked,
                   pipeline::CheckedWeights(weights, out.clothing->fitter.component_count(),
                                            weights.basis_id()));
  const Eigen::VectorXf w = checked.cast<float>();
  thread_local clothing::FitScratch scratch;
  const absl::Time start = absl::Now();
  const clothing::ClothingFitter& fitter = out.clothing->fitter;
  ASSIGN_OR_RETURN(out.pushed, own_body.empty()
                                   ? fitter.Fit(w, cleanup, scratch, positions)
                                   : fitter.FitToBody(w, own_body, cleanup, scratch, positions));
  out.compute = absl::Now() - start;
  return out;
}

// One garment size fitted to the weights, encoded as asked.
absl::StatusOr<v1::FittedGarment> FitOne(FitCatalog& catalog, absl::string_view tenant,
                                         const v1::AvatarWeights& weights,
                                         const ServedGarment& garment,
                                         absl::string_view garment_id, absl::string_view size,
                                         absl::string_view method_name,
                                         v1::PositionsEncoding encoding, bool with_metrics,
                                         bool cleanup, std::span<const float> own_body) {
  thread_local Eigen::VectorXf positions;
  ASSIGN_OR_RETURN(SizeFitted one, FitPositions(catalog, tenant, weights, garment, garment_id,
                                                size, method_name, cleanup, own_body,
                                                positions));
  const std::shared_ptr<const ServedClothing>& clothing = one.clothing;
  const std::string& method = one.method;
  const int64_t pushed = one.pushed;
  const absl::Duration compute = one.compute;

  v1::FittedGarment fitted;
  fitted.set_garment_id(std::string(garment_id));
  fitted.set_size(std::string(size));
  fitted.set_method(method);
  fitted.set_clothing_basis_id(clothing->content_id);
  fitted.set_clothing_basis_version(clothing->version);
  const std::span<const float> xyz(positions.data(), static_cast<size_t>(positions.size()));
  if (encoding == v1::POSITIONS_ENCODING_RAW) {
    *fitted.mutable_positions() = proto::EncodeRawPositions(xyz);
  } else {
    // In the topology's wire order: spatial neighbours in sequence, which Draco's sequential
    // coder predicts well, while the garment's own order (often coarse to fine) jumps.
    thread_local std::vector<float> wire;
    const auto& order = garment.topology.wire_order();
    wire.resize(xyz.size());
    for (int i = 0; i < order.size(); ++i) {
      for (int c = 0; c < 3; ++c) wire[3 * i + c] = xyz[3 * order[i] + c];
    }
    ASSIGN_OR_RETURN(*fitted.mutable_positions(), proto::EncodeDracoPositions(wire));
  }
  if (with_metrics) {
    fitted.mutable_metrics()->set_vertices_pushed_out(static_cast<uint32_t>(pushed));
    fitted.mutable_metrics()->set_compute_us(absl::ToDoubleMicroseconds(compute));
  }
  return fitted;
}

// The garment, and a refusal of weights of another avatar basis than the garment's (they
// would be silently mixed otherwise).
absl::StatusOr<std::shared_ptr<const ServedGarment>> GarmentForWeights(
    FitCatalog& catalog, absl::string_view tenant, absl::string_view garment_id,
    const v1::AvatarWeights& weights) {
  if (garment_id.empty()) return absl::InvalidArgumentError("garment_id is empty");
  ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                   catalog.Garment(tenant, garment_id));
  if (weights.basis_id() != garment->avatar_basis_id) {
    return absl::FailedPreconditionError(absl::StrCat(
        "the weights are of avatar basis '", weights.basis_id(), "'; garment ", garment_id,
        " is served on avatar basis ", garment->avatar_basis_id,
        ": project the avatar again (ProjectAvatar)"));
  }
  return garment;
}

// mean + components x weights, as 13,380 x 3 positions (m).
absl::StatusOr<core::Positions> BodyPositions(const pipeline::LoadedAvatarBasis& basis,
                                              const v1::AvatarWeights& weights) {
  ASSIGN_OR_RETURN(const Eigen::VectorXd w,
                   pipeline::CheckedWeights(weights, basis.pca.variances.size(),
                                            basis.message.id()));
  return pipeline::BodyOfWeights(basis, w);
}

absl::StatusOr<v1::Avatar> BodyOfWeights(const pipeline::LoadedAvatarBasis& basis,
                                         const v1::AvatarWeights& weights, bool draco) {
  ASSIGN_OR_RETURN(core::Positions positions, BodyPositions(basis, weights));
  return proto::AvatarFromPositions(positions, draco);
}

// A customer's own mesh further than this (m, mean over vertices) from the body of the
// weights is not the mesh they were projected from: the projection leaves 1 to 2 mm on
// held-out bodies and about 8 mm at worst.
constexpr double kMaxOwnBodyOffset = 0.010;

// The customer's own mesh of a fit request, as 3B floats (m), checked: a valid avatar, and
// within kMaxOwnBodyOffset of the body of `weights` on the garment's avatar basis. Empty
// without one.
absl::StatusOr<std::vector<float>> OwnBody(FitCatalog& catalog, const ServedGarment& garment,
                                           const v1::AvatarWeights& weights, bool has_body,
                                           const v1::Avatar& body) {
  if (!has_body) return std::vector<float>();
  ASSIGN_OR_RETURN(const core::Positions own, proto::AvatarPositions(body));
  ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::LoadedAvatarBasis> basis,
                   catalog.AvatarBasis(garment.avatar_basis_id));
  ASSIGN_OR_RETURN(const core::Positions of_weights, BodyPositions(*basis, weights));
  if (of_weights.rows() != own.rows()) {
    return absl::InvalidArgumentError(absl::StrCat("the body has ", own.rows(),
                                                   " vertices; avatar basis ",
                                                   garment.avatar_basis_id, " has ",
                                                   of_weights.rows()));
  }
  const double offset = (own - of_weights).rowwise().norm().mean();
  if (offset > kMaxOwnBodyOffset) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "the body lies %.1f mm (mean) from the body of the weights, more than the %.0f mm a "
        "projection leaves: it is not the avatar the weights were projected from "
        "(ProjectAvatar)",
        1000 * offset, 1000 * kMaxOwnBodyOffset));
  }
  return core::InterleavedFloats(own);
}

// How far beyond its example drapes a clothing basis is still trusted, as a multiple of their
// reach: the linear model's error grows quickly past about twice it.
constexpr double kReachFactor = 2.0;

int FitThreads(const FitServiceOptions& options) {
  if (options.threads > 0) return options.threads;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace

FitService::FitService(FitCatalog* catalog, const rpc::ApiKeyRegistry* keys,
                       const FitServiceOptions& options)
    : catalog_(catalog),
      keys_(keys),
      options_(options),
      calls_(FitThreads(options), options.max_calls_in_flight > 0
                                      ? options.max_calls_in_flight
                                      : 8 * FitThreads(options)) {}

grpc::ServerUnaryReactor* FitService::Admit(grpc::CallbackServerContext* context,
                                            std::function<absl::Status()> work) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  const bool admitted = calls_.TryRun(
      [this, work = std::move(work)] {
        if (options_.before_call) options_.before_call();
        return work();
      },
      [reactor](const absl::Status& status) { reactor->Finish(rpc::ToGrpcStatus(status)); });
  if (!admitted) {
    reactor->Finish(rpc::ToGrpcStatus(absl::ResourceExhaustedError(absl::StrCat(
        "the fit service is serving its limit of ", calls_.capacity(),
        " calls at once; retry after a backoff"))));
  }
  return reactor;
}

absl::StatusOr<std::shared_ptr<const pipeline::MeasurementModel>> FitService::MeasurementModelFor(
    const pipeline::LoadedAvatarBasis& basis) {
  const std::string& id = basis.message.id();
  const auto cached = [&]() -> std::shared_ptr<const pipeline::MeasurementModel> {
    std::lock_guard<std::mutex> lock(models_mutex_);
    const auto it = models_.find(id);
    return it == models_.end() ? nullptr : it->second;
  };
  if (auto model = cached()) return model;
  std::lock_guard<std::mutex> building(build_mutex_);
  // Another call may have built it while this one waited.
  if (auto model = cached()) return model;
  ASSIGN_OR_RETURN(pipeline::MeasurementModel built, pipeline::MeasurementModel::Build(basis));
  auto model = std::make_shared<const pipeline::MeasurementModel>(std::move(built));
  std::lock_guard<std::mutex> lock(models_mutex_);
  if (!models_.empty() && static_cast<int>(models_.size()) >= options_.max_measurement_models) {
    // Any entry: bases in use rarely outnumber the bound, and a rebuild costs only a second.
    models_.erase(models_.begin());
  }
  models_.emplace(id, model);
  return model;
}

grpc::ServerUnaryReactor* FitService::ProjectAvatar(grpc::CallbackServerContext* context,
                                                    const v1::ProjectAvatarRequest* request,
                                                    v1::AvatarProjection* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    if (request->population().empty()) return absl::InvalidArgumentError("population is empty");
    ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::LoadedAvatarBasis> basis,
                     catalog_->CurrentAvatarBasis(principal.tenant, request->population()));
    ASSIGN_OR_RETURN(core::Positions positions, proto::AvatarPositions(request->avatar()));
    core::Mesh avatar;
    avatar.positions = std::move(positions);
    ASSIGN_OR_RETURN(*response->mutable_weights(),
                     pipeline::ProjectAvatar(*basis, avatar));
    const v1::AvatarWeights& weights = response->weights();
    const double training = basis->pca.training_error.mean_mm;
    if (weights.mean_error_mm() > options_.ood_error_ratio * training) {
      response->add_reasons(absl::StrFormat(
          "reconstruction error %.2f mm is above %.1fx the population's %.2f mm",
          weights.mean_error_mm(), options_.ood_error_ratio, training));
    }
    for (int k = 0; k < weights.weights_size(); ++k) {
      const double sigmas = std::abs(weights.weights(k)) / std::sqrt(basis->pca.variances(k));
      if (sigmas > options_.ood_sigmas) {
        response->add_reasons(
            absl::StrFormat("component %d lies %.1f sigma from the mean", k, sigmas));
      }
    }
    response->set_out_of_distribution(response->reasons_size() > 0);
    if (request->with_body()) {
      ASSIGN_OR_RETURN(*response->mutable_body(),
                       BodyOfWeights(*basis, weights,
                                     request->encoding() != v1::POSITIONS_ENCODING_RAW));
    }
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::FitGarment(grpc::CallbackServerContext* context,
                                                 const v1::FitGarmentRequest* request,
                                                 v1::FittedGarment* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                     GarmentForWeights(*catalog_, principal.tenant, request->garment_id(),
                                       request->weights()));
    ASSIGN_OR_RETURN(const std::vector<float> own_body,
                     OwnBody(*catalog_, *garment, request->weights(), request->has_body(),
                             request->body()));
    RETURN_IF_ERROR(CheckAlive(*context));
    ASSIGN_OR_RETURN(*response,
                     FitOne(*catalog_, principal.tenant, request->weights(), *garment,
                            request->garment_id(), request->size(), request->method(),
                            request->encoding(), request->with_metrics(),
                            !request->skip_cleanup(), own_body));
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::FitOutfit(grpc::CallbackServerContext* context,
                                                const v1::FitOutfitRequest* request,
                                                v1::FitOutfitResponse* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    if (request->items().empty()) return absl::InvalidArgumentError("the outfit is empty");
    if (request->items_size() > options_.max_outfit_items) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "the outfit has ", request->items_size(), " items; at most ",
          options_.max_outfit_items));
    }
    // Decoded and checked once for the outfit: every item's garment is on the weights' basis.
    std::optional<std::vector<float>> own_body;
    for (const v1::OutfitItem& item : request->items()) {
      ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                       GarmentForWeights(*catalog_, principal.tenant, item.garment_id(),
                                         request->weights()));
      if (!own_body) {
        ASSIGN_OR_RETURN(own_body, OwnBody(*catalog_, *garment, request->weights(),
                                           request->has_body(), request->body()));
      }
      std::vector<std::string> sizes;
      if (item.size().empty()) {
        sizes.assign(garment->topology.sizes().begin(), garment->topology.sizes().end());
      } else {
        sizes.push_back(item.size());
      }
      int fitted = 0;
      for (const std::string& size : sizes) {
        RETURN_IF_ERROR(CheckAlive(*context));
        absl::StatusOr<v1::FittedGarment> one =
            FitOne(*catalog_, principal.tenant, request->weights(), *garment, item.garment_id(),
                   size, item.method(), request->encoding(), request->with_metrics(),
                   /*cleanup=*/true, *own_body);
        // Every size: only those with a published clothing basis.
        if (item.size().empty() && absl::IsNotFound(one.status())) continue;
        if (!one.ok()) return one.status();
        *response->add_garments() = *std::move(one);
        ++fitted;
      }
      if (fitted == 0) {
        return absl::NotFoundError(absl::StrCat("garment ", item.garment_id(),
                                                " has no published clothing basis"));
      }
    }
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::GetGarmentTopology(
    grpc::CallbackServerContext* context, const v1::GetGarmentTopologyRequest* request,
    v1::GarmentTopology* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    if (request->garment_id().empty()) return absl::InvalidArgumentError("garment_id is empty");
    ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                     catalog_->Garment(principal.tenant, request->garment_id()));
    *response = garment->topology;
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::AvatarFromMeasurements(
    grpc::CallbackServerContext* context, const v1::AvatarFromMeasurementsRequest* request,
    v1::AvatarFromMeasurementsResponse* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    if (request->population().empty()) return absl::InvalidArgumentError("population is empty");
    ASSIGN_OR_RETURN(const pipeline::MeasurementSet given,
                     pipeline::MeasurementsFromProto(request->measurements()));
    ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::LoadedAvatarBasis> basis,
                     catalog_->CurrentAvatarBasis(principal.tenant, request->population()));
    ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::MeasurementModel> model,
                     MeasurementModelFor(*basis));
    RETURN_IF_ERROR(CheckAlive(*context));
    ASSIGN_OR_RETURN(pipeline::MeasuredAvatar made,
                     pipeline::AvatarFromMeasurements(*basis, *model, given));

    v1::AvatarWeights* weights = response->mutable_weights();
    weights->set_basis_id(basis->message.id());
    weights->mutable_weights()->Assign(made.weights.data(),
                                       made.weights.data() + made.weights.size());
    ASSIGN_OR_RETURN(*response->mutable_avatar(),
                     proto::AvatarFromPositions(
                         made.avatar.positions,
                         /*draco=*/request->encoding() != v1::POSITIONS_ENCODING_RAW));
    for (const auto& [measurement, wanted, reached] : made.residuals) {
      v1::MeasurementResidual* residual = response->add_residuals();
      residual->set_name(std::string(body::MeasurementName(measurement)));
      residual->set_given(body::InTypedUnit(measurement, wanted));
      residual->set_reached(body::InTypedUnit(measurement, reached));
      residual->set_within_allowance(std::abs(reached - wanted) <=
                                     pipeline::MeasurementAllowance(measurement));
    }
    for (std::string& reason : made.out_of_distribution_reasons) {
      response->add_reasons(std::move(reason));
    }
    response->set_out_of_distribution(response->reasons_size() > 0);
    return absl::OkStatus();
  });
}

}  // namespace fitbase::fit

namespace fitbase::fit {

grpc::ServerUnaryReactor* FitService::AdviseSize(grpc::CallbackServerContext* context,
                                                 const v1::AdviseSizeRequest* request,
                                                 v1::SizeAdvice* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                     GarmentForWeights(*catalog_, principal.tenant, request->garment_id(),
                                       request->weights()));
    if (garment->advice == nullptr) {
      return absl::FailedPreconditionError(absl::StrCat("garment ", request->garment_id(),
                                                        " cannot be sized: ",
                                                        garment->advice_error.message()));
    }
    const pipeline::AdviceGarment& advice = *garment->advice;
    ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::LoadedAvatarBasis> basis,
                     catalog_->AvatarBasis(garment->avatar_basis_id));
    ASSIGN_OR_RETURN(core::Positions body_positions, BodyPositions(*basis, request->weights()));
    ASSIGN_OR_RETURN(core::Mesh mean, proto::MeshFromProto(basis->message.mean()));
    RETURN_IF_ERROR(CheckAlive(*context));
    ASSIGN_OR_RETURN(pipeline::AdviceBody body,
                     pipeline::MeasureAdviceBody(std::move(body_positions),
                                                 core::Triangulate(mean.faces)));

    // The sizes asked for, or every served one, in the garment's grading order.
    std::vector<int> sizes;
    for (int i = 0; i < static_cast<int>(advice.size_names.size()); ++i) {
      const std::string& name = advice.size_names[i];
      if (request->sizes().empty() ||
          std::find(request->sizes().begin(), request->sizes().end(), name) !=
              request->sizes().end()) {
        sizes.push_back(i);
      }
    }
    for (const std::string& name : request->sizes()) {
      if (std::find(advice.size_names.begin(), advice.size_names.end(), name) ==
          advice.size_names.end()) {
        return absl::NotFoundError(absl::StrCat("garment ", request->garment_id(),
                                                " has no size '", name, "'; it has ",
                                                absl::StrJoin(advice.size_names, ",")));
      }
    }
    std::vector<int> judged_sizes;
    std::vector<pipeline::SizeJudgement> judged;
    Eigen::VectorXd reach;
    Eigen::VectorXf flat;
    for (int size : sizes) {
      RETURN_IF_ERROR(CheckAlive(*context));
      absl::StatusOr<SizeFitted> fitted =
          FitPositions(*catalog_, principal.tenant, request->weights(), *garment,
                       request->garment_id(), advice.size_names[size], request->method(),
                       /*cleanup=*/true, /*own_body=*/{}, flat);
      // Every size: only those with a published clothing basis.
      if (request->sizes().empty() && absl::IsNotFound(fitted.status())) continue;
      if (!fitted.ok()) return fitted.status();
      reach = fitted->clothing->example_reach;
      const core::Positions positions =
          Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
              flat.data(), flat.size() / 3, 3)
              .cast<double>();
      ASSIGN_OR_RETURN(pipeline::SizeJudgement one,
                       pipeline::JudgeSize(advice, size, body, positions));
      judged_sizes.push_back(size);
      judged.push_back(std::move(one));
    }
    if (judged.empty()) {
      return absl::NotFoundError(absl::StrCat("garment ", request->garment_id(),
                                              " has no published clothing basis"));
    }
    *response = pipeline::AssembleAdvice(advice, judged_sizes, judged, /*with_maps=*/true);
    response->set_garment_id(request->garment_id());

    // Out of distribution: a weight far from the avatar population, or far beyond the drapes
    // the clothing basis was built from (the model extrapolates there).
    const v1::AvatarWeights& weights = request->weights();
    for (int k = 0; k < weights.weights_size(); ++k) {
      const double sigmas = std::abs(weights.weights(k)) / std::sqrt(basis->pca.variances(k));
      if (sigmas > options_.ood_sigmas) {
        response->add_ood_reasons(
            absl::StrFormat("component %d lies %.1f sigma from the mean", k, sigmas));
      } else if (k < reach.size() && reach(k) > 0 &&
                 std::abs(weights.weights(k)) > kReachFactor * reach(k)) {
        response->add_ood_reasons(absl::StrFormat(
            "component %d lies %.1fx as far out as the drapes the garment was fitted from", k,
            std::abs(weights.weights(k)) / reach(k)));
      }
    }
    response->set_out_of_distribution(response->ood_reasons_size() > 0);
    if (response->out_of_distribution()) {
      // The advice stands on an extrapolated fit: say so in the confidence as well.
      response->set_confidence(response->confidence() * 0.5);
    }
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::ListShopGarments(grpc::CallbackServerContext* context,
                                                   const v1::ListShopGarmentsRequest* /*request*/,
                                                   v1::ShopGarments* response) {
  return Admit(context, [this, context, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    ASSIGN_OR_RETURN(std::vector<std::string> ids, catalog_->ListGarmentIds(principal.tenant));
    ASSIGN_OR_RETURN(const auto populations, catalog_->CurrentAvatarBases(principal.tenant));
    for (const std::string& id : ids) {
      RETURN_IF_ERROR(CheckAlive(*context));
      ASSIGN_OR_RETURN(std::shared_ptr<const ServedGarment> garment,
                       catalog_->Garment(principal.tenant, id));
      v1::GarmentSummary summary;
      summary.set_garment_id(id);
      summary.set_name(garment->topology.name());
      if (garment->advice != nullptr) {
        summary.set_garment_type(std::string(clothing::GarmentTypeName(garment->advice->type)));
      }
      for (const auto& [population, basis_id] : populations) {
        if (basis_id == garment->avatar_basis_id) summary.set_population(population);
      }
      for (const std::string& size : garment->topology.sizes()) {
        for (const char* method : kDefaultMethods) {
          if (catalog_->Clothing({principal.tenant, id, size, garment->avatar_basis_id, method})
                  .ok()) {
            summary.add_sizes(size);
            break;
          }
        }
      }
      // A garment a customer can be fitted to: served, on a current avatar basis.
      if (summary.sizes_size() > 0 && !summary.population().empty()) {
        *response->add_garments() = std::move(summary);
      }
    }
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* FitService::GetBodyTopology(grpc::CallbackServerContext* context,
                                                      const v1::GetBodyTopologyRequest* request,
                                                      v1::BodyTopology* response) {
  return Admit(context, [this, context, request, response]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, AdmitCustomer(*context, *keys_));
    if (request->population().empty()) return absl::InvalidArgumentError("population is empty");
    ASSIGN_OR_RETURN(std::shared_ptr<const pipeline::LoadedAvatarBasis> basis,
                     catalog_->CurrentAvatarBasis(principal.tenant, request->population()));
    response->set_avatar_basis_id(basis->message.id());
    *response->mutable_faces() = basis->message.mean();
    response->mutable_faces()->clear_positions();
    return absl::OkStatus();
  });
}

}  // namespace fitbase::fit
