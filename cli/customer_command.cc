// fitbase customer project|from-measurements|fit|outfit|advise: the fit service's calls as a
// shop makes them.
#include <filesystem>
#include <iostream>
#include <optional>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "cli/cli_context.h"
#include "cli/customer_client.h"
#include "cli/remote_flags.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "fitbase/v1/fit_service.grpc.pb.h"
#include "pipeline/avatar_file.h"
#include "proto/avatar_codec.h"
#include "proto/draco_codec.h"
#include "proto/json_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct CustomerFlags {
  RemoteFlags remote{.address = "127.0.0.1:7402", .api_key_file = {}, .timeout_seconds = 30};
  std::string avatar;
  std::string measurements;
  std::string population = "women";
  bool draco = false;
  std::string weights;
  std::string garment;
  std::string size = "M";
  std::string method;
  bool raw = false;
  std::string garments;
  std::string sizes;
  std::string out;
};

absl::Status RunProject(const CustomerFlags& flags) {
  ASSIGN_OR_RETURN(core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
  v1::ProjectAvatarRequest request;
  request.set_population(flags.population);
  ASSIGN_OR_RETURN(*request.mutable_avatar(),
                   proto::AvatarFromPositions(avatar.positions, flags.draco));
  auto stub = v1::FitService::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::AvatarProjection projection;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->ProjectAvatar(context.get(), request, &projection)));
  RETURN_IF_ERROR(core::WriteFileAtomically(flags.out, proto::ToJson(projection.weights())));
  std::cout << absl::StrFormat("weights on basis %.12s: %d components, reconstruction %.2f mm",
                               projection.weights().basis_id(),
                               projection.weights().weights_size(),
                               projection.weights().mean_error_mm());
  for (const std::string& reason : projection.reasons()) {
    std::cout << "\n  out of distribution: " << reason;
  }
  std::cout << "\nwrote " << flags.out << "\n";
  return absl::OkStatus();
}

absl::Status RunFromMeasurements(const CliContext& context, const CustomerFlags& flags) {
  ASSIGN_OR_RETURN(const std::string json, core::ReadFileToString(flags.measurements));
  v1::AvatarFromMeasurementsRequest request;
  if (absl::Status parsed = proto::ParseJson(json, request.mutable_measurements());
      !parsed.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(flags.measurements, ": ", parsed.message()));
  }
  request.set_population(flags.population);
  // The format carries no faces: every body of the topology has those of base.obj's body group.
  ASSIGN_OR_RETURN(const core::Mesh base, core::ReadObj(ResolveDataDir(context) / "base.obj"));
  auto stub = v1::FitService::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> call,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::AvatarFromMeasurementsResponse response;
  RETURN_IF_ERROR(
      rpc::FromGrpcStatus(stub->AvatarFromMeasurements(call.get(), request, &response)));
  ASSIGN_OR_RETURN(core::Positions positions, proto::AvatarPositions(response.avatar()));
  const core::Mesh avatar{.topology_id = std::string(body::kBodyTopologyId),
                          .positions = std::move(positions),
                          .faces = body::BodyFacesOf(base.faces)};
  RETURN_IF_ERROR(core::WriteObj(flags.out, avatar));
  if (!flags.weights.empty()) {
    RETURN_IF_ERROR(core::WriteFileAtomically(flags.weights, proto::ToJson(response.weights())));
  }
  for (const v1::MeasurementResidual& residual : response.residuals()) {
    const absl::StatusOr<body::Measurement> measurement =
        body::ParseMeasurement(residual.name());
    const absl::string_view unit = measurement.ok() ? body::TypedUnit(*measurement) : "cm";
    std::cout << absl::StrFormat("%s %.1f %s -> %.1f %s%s\n", residual.name(),
                                 residual.given(), unit, residual.reached(), unit,
                                 residual.within_allowance() ? "" : "  (outside the allowance)");
  }
  for (const std::string& reason : response.reasons()) {
    std::cout << "out of distribution: " << reason << "\n";
  }
  std::cout << absl::StrFormat("wrote %s (basis %.12s, %d weights)\n", flags.out,
                               response.weights().basis_id(),
                               response.weights().weights_size());
  return absl::OkStatus();
}

absl::StatusOr<v1::AvatarWeights> ReadWeights(const std::string& path) {
  ASSIGN_OR_RETURN(std::string json, core::ReadFileToString(path));
  v1::AvatarWeights weights;
  RETURN_IF_ERROR(proto::ParseJson(json, &weights));
  return weights;
}

absl::Status RunFit(const CustomerFlags& flags) {
  ASSIGN_OR_RETURN(v1::AvatarWeights weights, ReadWeights(flags.weights));
  std::optional<v1::Avatar> body;
  if (!flags.avatar.empty()) {
    ASSIGN_OR_RETURN(const core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
    ASSIGN_OR_RETURN(body, proto::AvatarFromPositions(avatar.positions, flags.draco));
  }
  CustomerClient client(flags.remote);
  ASSIGN_OR_RETURN(v1::FittedGarment fitted,
                   client.Fit(weights, flags.garment, flags.size, flags.method, flags.raw,
                              body ? &*body : nullptr));
  RETURN_IF_ERROR(client.WriteObj(fitted, flags.out));
  std::cout << absl::StrFormat(
      "%s size %s (%s, clothing basis %.12s v%d): %d bytes of positions, %d vertices pushed "
      "out, %.0f us to fit\nwrote %s\n",
      fitted.garment_id().substr(0, 12), fitted.size(), fitted.method(),
      fitted.clothing_basis_id(), fitted.clothing_basis_version(),
      fitted.positions().ByteSizeLong(), fitted.metrics().vertices_pushed_out(),
      fitted.metrics().compute_us(), flags.out);
  return absl::OkStatus();
}

absl::Status RunAdvise(const CustomerFlags& flags) {
  ASSIGN_OR_RETURN(v1::AvatarWeights weights, ReadWeights(flags.weights));
  v1::AdviseSizeRequest request;
  *request.mutable_weights() = weights;
  request.set_garment_id(flags.garment);
  request.set_method(flags.method);
  for (absl::string_view size : absl::StrSplit(flags.sizes, ',', absl::SkipWhitespace())) {
    request.add_sizes(std::string(size));
  }
  auto stub = v1::FitService::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::SizeAdvice advice;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->AdviseSize(context.get(), request, &advice)));
  std::cout << absl::StrFormat("We recommend %s (%.0f%% confidence; ease bands of a %s)\n",
                               advice.recommended_size(), 100 * advice.confidence(),
                               advice.garment_type());
  for (const std::string& reason : advice.reasons()) std::cout << "  " << reason << "\n";
  for (const std::string& reason : advice.ood_reasons()) {
    std::cout << "  out of distribution: " << reason << "\n";
  }
  for (const v1::SizeFit& size : advice.sizes()) {
    std::cout << absl::StrFormat("%-5s %-8s %-15s %9s %9s %9s %8s\n", size.size(),
                                 size.verdict(), "region", "body_cm", "garment", "ease_cm",
                                 "stretch%");
    for (const v1::RegionFit& region : size.regions()) {
      std::cout << absl::StrFormat("%-14s %-15s %9.1f %9.1f %+9.1f %8.1f  %s\n", "",
                                   region.region(), region.body_cm(), region.garment_cm(),
                                   region.ease_cm(), region.stretch_pct(), region.verdict());
    }
  }
  if (!flags.out.empty()) {
    RETURN_IF_ERROR(core::WriteFileAtomically(flags.out, proto::ToJson(advice)));
    std::cout << "wrote " << flags.out << " (with the per-vertex fit maps)\n";
  }
  return absl::OkStatus();
}

absl::Status RunOutfit(const CustomerFlags& flags) {
  ASSIGN_OR_RETURN(v1::AvatarWeights weights, ReadWeights(flags.weights));
  v1::FitOutfitRequest request;
  *request.mutable_weights() = weights;
  request.set_with_metrics(true);
  request.set_encoding(flags.raw ? v1::POSITIONS_ENCODING_RAW : v1::POSITIONS_ENCODING_DRACO);
  for (absl::string_view entry : absl::StrSplit(flags.garments, ',', absl::SkipWhitespace())) {
    const std::vector<std::string> parts = absl::StrSplit(entry, absl::MaxSplits(':', 1));
    v1::OutfitItem* item = request.add_items();
    item->set_garment_id(parts[0]);
    if (parts.size() > 1) item->set_size(parts[1]);
    item->set_method(flags.method);
  }
  CustomerClient client(flags.remote);
  ASSIGN_OR_RETURN(v1::FitOutfitResponse outfit, client.Outfit(request));
  std::filesystem::create_directories(flags.out);
  for (const v1::FittedGarment& fitted : outfit.garments()) {
    const std::filesystem::path path =
        std::filesystem::path(flags.out) /
        absl::StrCat(fitted.garment_id().substr(0, 12), "-", fitted.size(), ".obj");
    RETURN_IF_ERROR(client.WriteObj(fitted, path));
    std::cout << "wrote " << path.string() << "\n";
  }
  return absl::OkStatus();
}

}  // namespace

void AddCustomerCommands(CLI::App& app, CliContext& context) {
  CLI::App* customer =
      app.add_subcommand("customer", "Calls of the fit service, as a shop makes them");
  customer->require_subcommand(1);
  auto flags = std::make_shared<CustomerFlags>();

  CLI::App* project = customer->add_subcommand("project", "Project a customer's avatar");
  AddRemoteOptions(project, flags->remote, "--server");
  project->add_option("--avatar", flags->avatar, "Avatar OBJ (13,380 vertices, meters)")
      ->required();
  project->add_option("--population", flags->population, "The basis's population (women)");
  project->add_flag("--draco", flags->draco, "Send the avatar Draco-compressed");
  project->add_option("--out", flags->out, "Weights JSON")->required();
  project->callback(
      [&context, flags] { context.action = [flags] { return RunProject(*flags); }; });

  CLI::App* from_measurements = customer->add_subcommand(
      "from-measurements", "Make the avatar of a customer's typed measurements (cm, kg)");
  AddRemoteOptions(from_measurements, flags->remote, "--server");
  from_measurements->add_option("--population", flags->population,
                                "The basis's population (women)");
  from_measurements
      ->add_option("--measurements", flags->measurements,
                   "JSON: any of the keys `avatar measure --json` prints, stature_cm at least")
      ->required();
  from_measurements->add_option("--out", flags->out, "Avatar OBJ (13,380 vertices, meters)")
      ->required();
  from_measurements->add_option("--weights", flags->weights,
                                "Also write the weights JSON (what `customer fit` reads)");
  from_measurements->callback([&context, flags] {
    context.action = [&context, flags] { return RunFromMeasurements(context, *flags); };
  });

  CLI::App* fit = customer->add_subcommand("fit", "Fit one garment size to the weights");
  AddRemoteOptions(fit, flags->remote, "--server");
  fit->add_option("--weights", flags->weights, "Weights JSON (customer project)")->required();
  fit->add_option("--garment", flags->garment, "Garment id")->required();
  fit->add_option("--size", flags->size, "Size (default M)");
  fit->add_option("--method", flags->method, "kernel, linear, quadratic or paper (default: kernel where built, else linear)");
  fit->add_flag("--raw", flags->raw, "Ask for raw float32 positions instead of Draco");
  fit->add_option("--avatar", flags->avatar,
                  "Fit to this avatar OBJ, the mesh the weights were projected from, instead of "
                  "the body of the weights");
  fit->add_flag("--draco", flags->draco, "Send --avatar Draco-encoded instead of raw");
  fit->add_option("--out", flags->out, "Fitted garment OBJ")->required();
  fit->callback([&context, flags] { context.action = [flags] { return RunFit(*flags); }; });

  CLI::App* outfit = customer->add_subcommand("outfit", "Fit several garments in one call");
  AddRemoteOptions(outfit, flags->remote, "--server");
  outfit->add_option("--weights", flags->weights, "Weights JSON (customer project)")
      ->required();
  outfit->add_option("--garments", flags->garments,
                     "ID[:SIZE],...: a garment without size gets every size")
      ->required();
  outfit->add_option("--method", flags->method, "kernel, linear, quadratic or paper (default: kernel where built, else linear)");
  outfit->add_flag("--raw", flags->raw, "Ask for raw float32 positions instead of Draco");
  outfit->add_option("--out", flags->out, "Output folder")->required();
  outfit->callback([&context, flags] { context.action = [flags] { return RunOutfit(*flags); }; });

  CLI::App* advise = customer->add_subcommand(
      "advise", "Which size to buy: every size judged at the body's girths, with a fit map");
  AddRemoteOptions(advise, flags->remote, "--server");
  advise->add_option("--weights", flags->weights, "Weights JSON (customer project)")
      ->required();
  advise->add_option("--garment", flags->garment, "Garment id")->required();
  advise->add_option("--sizes", flags->sizes, "Comma-separated sizes (default: every built one)");
  advise->add_option("--method", flags->method, "kernel, linear, quadratic or paper (default: kernel where built, else linear)");
  advise->add_option("--out", flags->out, "Also write the whole advice as JSON here");
  advise->callback([&context, flags] { context.action = [flags] { return RunAdvise(*flags); }; });
}

}  // namespace fitbase::cli
