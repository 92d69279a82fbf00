#include "services/build/catalog_service.h"

#include <algorithm>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "body/population_sampler.h"
#include "core/status_macros.h"
#include "pipeline/avatar_basis_builder.h"
#include "pipeline/garment_importer.h"
#include "pipeline/population_folder.h"
#include "proto/avatar_basis_codec.h"
#include "proto/message_file.h"
#include "services/rpc/call_auth.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::build {
namespace {

// A population is sampled and decomposed inside the call: bound it like the CLI's demo sizes.
constexpr uint32_t kMaxPopulation = 2000;

absl::StatusOr<rpc::Principal> AdmitWriter(const grpc::ServerContext& context,
                                      const rpc::ApiKeyRegistry& keys, absl::string_view action) {
  ASSIGN_OR_RETURN(rpc::Principal principal, rpc::AuthenticateCall(context, keys));
  RETURN_IF_ERROR(rpc::RequireRole(principal, {rpc::Role::kIngestion}, action));
  return principal;
}

pipeline::SourceFile ToSourceFile(const v1::SourceFile& file) {
  return {file.name(), file.content()};
}

absl::StatusOr<v1::AvatarBasis> ReadAvatarBasis(const storage::AssetStore& store,
                                                absl::string_view id) {
  ASSIGN_OR_RETURN(std::string bytes, store.GetAvatarBasis(id));
  v1::AvatarBasis basis;
  if (!basis.ParseFromString(bytes)) {
    return absl::DataLossError(absl::StrCat("stored avatar basis ", id, " does not parse"));
  }
  return basis;
}

absl::StatusOr<v1::UploadGarmentResponse> Upload(storage::AssetStore& store,
                                                 const body::BodyModel& model,
                                                 absl::string_view tenant,
                                                 const v1::UploadGarmentRequest& request) {
  if (request.avatar_basis_id().empty()) {
    return absl::InvalidArgumentError("avatar_basis_id is empty");
  }
  ASSIGN_OR_RETURN(v1::AvatarBasis basis, ReadAvatarBasis(store, request.avatar_basis_id()));
  if (request.obj().content().empty()) return absl::InvalidArgumentError("obj is empty");
  pipeline::GarmentImportRequest import{.obj = ToSourceFile(request.obj()),
                                        .mhclo = std::nullopt,
                                        .name = request.name(),
                                        .sizes = {request.sizes().begin(), request.sizes().end()},
                                        .garment_type = request.garment_type(),
                                        .size_meshes = {},
                                        .cuffs = request.cuffs()};
  if (request.has_mhclo()) import.mhclo = ToSourceFile(request.mhclo());
  for (const auto& [size, file] : request.size_meshes()) {
    import.size_meshes[size] = ToSourceFile(file);
  }
  ASSIGN_OR_RETURN(v1::Garment garment, pipeline::ImportGarment(model, basis, import));
  const bool existed = store.GetGarment(tenant, garment.id()).ok();
  RETURN_IF_ERROR(
      store.PutGarment(tenant, garment.id(), proto::SerializeDeterministically(garment)));
  v1::UploadGarmentResponse response;
  response.set_garment_id(garment.id());
  response.set_created(!existed);
  response.set_vertex_count(garment.template_mesh().vertex_count());
  return response;
}

absl::StatusOr<v1::AvatarBasis> BasisOfRequest(const body::BodyModel& model,
                                               const v1::PublishAvatarBasisRequest& request) {
  if (request.has_basis()) {
    // Validated as a fit would read it: shapes, orthonormal sizes, finite values.
    RETURN_IF_ERROR(proto::PcaBasisFromProto(request.basis()).status());
    if (request.basis().id().empty()) return absl::InvalidArgumentError("the basis has no id");
    return request.basis();
  }
  if (!request.has_spec()) return absl::InvalidArgumentError("give a population spec or a basis");
  const v1::PopulationSpec& spec = request.spec();
  ASSIGN_OR_RETURN(body::PopulationPreset preset, body::ParsePopulationPreset(spec.preset()));
  if (spec.count() > kMaxPopulation) {
    return absl::ResourceExhaustedError(
        absl::StrCat("count ", spec.count(), " is above the limit of ", kMaxPopulation));
  }
  ASSIGN_OR_RETURN(pipeline::Population population,
                   pipeline::SamplePopulation(model, preset, spec.seed(), spec.count()));
  core::ComponentSelection selection;
  switch (spec.selection().rule_case()) {
    case v1::ComponentSelection::kComponentCount:
      selection.rule = core::ComponentSelection::Rule::kCount;
      selection.count = static_cast<int>(spec.selection().component_count());
      break;
    case v1::ComponentSelection::kVarianceFraction:
      selection.rule = core::ComponentSelection::Rule::kVarianceFraction;
      selection.variance_fraction = spec.selection().variance_fraction();
      break;
    case v1::ComponentSelection::kMaxMeanErrorMm:
      selection.max_mean_error_mm = spec.selection().max_mean_error_mm();
      break;
    case v1::ComponentSelection::RULE_NOT_SET:
      break;
  }
  return pipeline::BuildAvatarBasis(population, selection);
}

// A checkpoint name that cannot leave the checkpoint folder.
absl::Status CheckCheckpointName(absl::string_view name) {
  const bool valid = !name.empty() && name.size() <= 64 && name[0] != '.' &&
                     std::all_of(name.begin(), name.end(), [](char c) {
                       return absl::ascii_isalnum(static_cast<unsigned char>(c)) || c == '.' ||
                              c == '_' || c == '-';
                     });
  if (!valid) {
    return absl::InvalidArgumentError(absl::StrCat(
        "checkpoint name '", name, "' must be 1-64 of [A-Za-z0-9._-], not starting with '.'"));
  }
  return absl::OkStatus();
}

}  // namespace

grpc::Status CatalogService::CreateCheckpoint(grpc::ServerContext* context,
                                              const v1::CreateCheckpointRequest* request,
                                              v1::CreateCheckpointResponse* response) {
  absl::Status status = [&]() -> absl::Status {
    ASSIGN_OR_RETURN(rpc::Principal principal, rpc::AuthenticateCall(*context, *keys_));
    RETURN_IF_ERROR(rpc::RequireRole(principal, {}, "create checkpoints"));
    RETURN_IF_ERROR(CheckCheckpointName(request->name()));
    const std::filesystem::path dir = checkpoint_root_ / request->name();
    if (std::filesystem::exists(dir)) {
      return absl::AlreadyExistsError(absl::StrCat("checkpoint ", dir.string(), " exists"));
    }
    std::error_code error;
    std::filesystem::create_directories(checkpoint_root_, error);
    if (error) {
      return absl::InternalError(
          absl::StrCat("cannot create ", checkpoint_root_.string(), ": ", error.message()));
    }
    RETURN_IF_ERROR(store_->CreateCheckpoint(dir));
    response->set_path(dir.string());
    return absl::OkStatus();
  }();
  return rpc::ToGrpcStatus(status);
}

grpc::Status CatalogService::UploadGarment(grpc::ServerContext* context,
                                           const v1::UploadGarmentRequest* request,
                                           v1::UploadGarmentResponse* response) {
  absl::StatusOr<rpc::Principal> principal = AdmitWriter(*context, *keys_, "upload garments");
  if (!principal.ok()) return rpc::ToGrpcStatus(principal.status());
  absl::StatusOr<v1::UploadGarmentResponse> uploaded =
      Upload(*store_, *model_, principal->tenant, *request);
  if (!uploaded.ok()) return rpc::ToGrpcStatus(uploaded.status());
  *response = *std::move(uploaded);
  return grpc::Status::OK;
}

grpc::Status CatalogService::ListGarments(grpc::ServerContext* context,
                                          const v1::ListGarmentsRequest*,
                                          v1::ListGarmentsResponse* response) {
  absl::StatusOr<rpc::Principal> principal = AdmitWriter(*context, *keys_, "list garments");
  if (!principal.ok()) return rpc::ToGrpcStatus(principal.status());
  absl::StatusOr<std::vector<std::string>> ids = store_->ListGarmentIds(principal->tenant);
  if (!ids.ok()) return rpc::ToGrpcStatus(ids.status());
  response->mutable_garment_ids()->Assign(ids->begin(), ids->end());
  return grpc::Status::OK;
}

grpc::Status CatalogService::PublishAvatarBasis(grpc::ServerContext* context,
                                                const v1::PublishAvatarBasisRequest* request,
                                                v1::PublishAvatarBasisResponse* response) {
  absl::StatusOr<rpc::Principal> principal = AdmitWriter(*context, *keys_, "publish avatar bases");
  if (!principal.ok()) return rpc::ToGrpcStatus(principal.status());
  absl::StatusOr<v1::AvatarBasis> basis = BasisOfRequest(*model_, *request);
  if (!basis.ok()) return rpc::ToGrpcStatus(basis.status());
  const absl::Status published =
      store_->PublishAvatarBasis(principal->tenant, request->population(), basis->id(),
                                 proto::SerializeDeterministically(*basis));
  if (!published.ok()) return rpc::ToGrpcStatus(published);
  response->set_avatar_basis_id(basis->id());
  response->set_component_count(basis->component_count());
  return grpc::Status::OK;
}

grpc::Status CatalogService::GetAvatarBasis(grpc::ServerContext* context,
                                            const v1::GetAvatarBasisRequest* request,
                                            v1::AvatarBasis* response) {
  absl::StatusOr<rpc::Principal> principal = AdmitWriter(*context, *keys_, "read avatar bases");
  if (!principal.ok()) return rpc::ToGrpcStatus(principal.status());
  std::string id = request->avatar_basis_id();
  if (id.empty()) {
    absl::StatusOr<std::string> current =
        store_->GetCurrentAvatarBasisId(principal->tenant, request->population());
    if (!current.ok()) return rpc::ToGrpcStatus(current.status());
    id = *std::move(current);
  }
  absl::StatusOr<v1::AvatarBasis> basis = ReadAvatarBasis(*store_, id);
  if (!basis.ok()) return rpc::ToGrpcStatus(basis.status());
  *response = *std::move(basis);
  return grpc::Status::OK;
}

}  // namespace fitbase::build
