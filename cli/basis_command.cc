// fitbase basis build|info|project|example|eval: the PCA avatar basis.
#include <cmath>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "body/body_model.h"
#include "cli/cli_context.h"
#include "cli/remote_flags.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "fitbase/v1/catalog.grpc.pb.h"
#include "pipeline/avatar_basis_builder.h"
#include "pipeline/avatar_from_measurements.h"
#include "pipeline/avatar_file.h"
#include "pipeline/avatar_projection.h"
#include "pipeline/population_folder.h"
#include "proto/avatar_basis_codec.h"
#include "proto/json_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"
#include "services/rpc/channel.h"
#include "services/rpc/grpc_status.h"

namespace fitbase::cli {
namespace {

struct BasisFlags {
  std::string population;
  std::string basis;
  std::string avatar;
  std::string out;
  double max_error_mm = 1.0;
  int components = 0;
  double variance = 0.0;
  int component = 0;
  double sigma = 1.0;
  bool json = false;
  RemoteFlags remote;
  std::string population_name;
  std::string preset;
  uint32_t count = 300;
  uint64_t seed = 1;
};

absl::Status RunBuild(const BasisFlags& flags, const CLI::App& command) {
  core::ComponentSelection selection;
  const int rules = static_cast<int>(command.count("--max-error-mm") > 0) +
                    static_cast<int>(command.count("--components") > 0) +
                    static_cast<int>(command.count("--variance") > 0);
  if (rules > 1) {
    return absl::InvalidArgumentError(
        "give at most one of --max-error-mm, --components and --variance");
  }
  if (command.count("--components") > 0) {
    selection.rule = core::ComponentSelection::Rule::kCount;
    selection.count = flags.components;
  } else if (command.count("--variance") > 0) {
    selection.rule = core::ComponentSelection::Rule::kVarianceFraction;
    selection.variance_fraction = flags.variance;
  } else if (!(flags.max_error_mm > 0) || !std::isfinite(flags.max_error_mm)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--max-error-mm is ", flags.max_error_mm, "; expected a positive number"));
  } else {
    selection.max_mean_error_mm = flags.max_error_mm;
  }
  ASSIGN_OR_RETURN(pipeline::Population population,
                   pipeline::ReadPopulationFolder(flags.population));
  ASSIGN_OR_RETURN(v1::AvatarBasis basis, pipeline::BuildAvatarBasis(population, selection));
  RETURN_IF_ERROR(proto::WriteMessageFile(flags.out, basis));
  double explained = 0;
  for (double r : basis.explained_variance_ratio()) explained += r;
  std::cout << absl::StrFormat(
      "basis %s: %d components from %d avatars, %.2f%% of the variance, training error mean "
      "%.3f mm, max %.3f mm\nwrote %s\n",
      basis.id(), basis.component_count(), population.samples.cols(), 100 * explained,
      basis.training_mean_error_mm(), basis.training_max_error_mm(), flags.out);
  return absl::OkStatus();
}

absl::Status RunInfo(const BasisFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  const v1::AvatarBasis& m = basis.message;
  std::cout << "id          " << m.id() << "\n"
            << "topology    " << m.topology_id() << " (" << m.mean().vertex_count()
            << " vertices)\n"
            << "population  preset "
            << (m.population().preset().empty() ? "-" : m.population().preset()) << ", seed "
            << m.population().seed() << ", " << m.population().count() << " avatars\n"
            << "selection   " << proto::ToJson(m.selection()) << "\n"
            << absl::StrFormat("training    mean error %.3f mm, max %.3f mm\n",
                               m.training_mean_error_mm(), m.training_max_error_mm())
            << "components  " << m.component_count() << "\n\n"
            << "sigma: standard deviation of the weight (m); rms_mm: per-vertex RMS displacement"
               " of a 1-sigma step\n"
            << "  k      sigma    rms_mm  explained%  cumulative%\n";
  double cumulative = 0;
  for (uint32_t k = 0; k < m.component_count(); ++k) {
    cumulative += m.explained_variance_ratio(k);
    const double sigma = std::sqrt(m.variances(k));
    std::cout << absl::StrFormat(
        "%3d %10.4f %9.2f %11.4f %12.4f\n", k, sigma,
        1000 * sigma / std::sqrt(static_cast<double>(m.mean().vertex_count())),
        100 * m.explained_variance_ratio(k), 100 * cumulative);
  }
  return absl::OkStatus();
}

absl::Status RunProject(const BasisFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  ASSIGN_OR_RETURN(core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
  ASSIGN_OR_RETURN(const v1::AvatarWeights result, pipeline::ProjectAvatar(basis, avatar));
  if (flags.json) {
    std::cout << proto::ToJson(result) << "\n";
    return absl::OkStatus();
  }
  std::cout << "basis    " << result.basis_id() << "\nweights ";
  for (double w : result.weights()) std::cout << absl::StrFormat(" %.6g", w);
  std::cout << absl::StrFormat("\nreconstruction error: mean %.3f mm, max %.3f mm\n",
                               result.mean_error_mm(), result.max_error_mm());
  return absl::OkStatus();
}

absl::Status RunExample(const BasisFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  const int n = static_cast<int>(basis.pca.components.cols());
  if (flags.component < 0 || flags.component >= n) {
    return absl::InvalidArgumentError(absl::StrCat("--component is ", flags.component,
                                                   "; this basis has components 0 to ", n - 1));
  }
  if (!std::isfinite(flags.sigma)) return absl::InvalidArgumentError("--sigma must be finite");
  const Eigen::VectorXd x = core::ExampleFromComponent(basis.pca, flags.component, flags.sigma);
  ASSIGN_OR_RETURN(core::Mesh mesh, proto::MeshFromProto(basis.message.mean()));
  mesh.positions = Eigen::Map<const core::Positions>(x.data(), mesh.vertex_count(), 3);
  RETURN_IF_ERROR(core::WriteObj(flags.out, mesh));
  std::cout << "wrote " << flags.out << ": mean + " << flags.sigma << " sigma x component "
            << flags.component << "\n";
  return absl::OkStatus();
}

absl::Status RunEval(const BasisFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  ASSIGN_OR_RETURN(pipeline::Population population,
                   pipeline::ReadPopulationFolder(flags.population));
  double sum_mean = 0, worst_mean = 0, worst_max = 0;
  const Eigen::Index count = population.samples.cols();
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::VectorXd x = population.samples.col(i);
    const core::ReconstructionError error = core::MeasureReconstructionError(
        x, core::ReconstructFromWeights(basis.pca, core::ProjectOntoBasis(basis.pca, x)));
    sum_mean += error.mean_mm;
    worst_mean = std::max(worst_mean, error.mean_mm);
    worst_max = std::max(worst_max, error.max_mm);
  }
  std::cout << absl::StrFormat(
      "%d avatars of %s on basis %.12s (%d components): per-vertex error mean %.3f mm "
      "(worst avatar %.3f mm), max %.3f mm\n",
      count, flags.population, basis.message.id(), basis.message.component_count(),
      sum_mean / static_cast<double>(count), worst_mean, worst_max);
  return absl::OkStatus();
}

absl::Status RunEvalMeasurements(const BasisFlags& flags) {
  ASSIGN_OR_RETURN(pipeline::LoadedAvatarBasis basis, pipeline::LoadAvatarBasis(flags.basis));
  ASSIGN_OR_RETURN(pipeline::Population population,
                   pipeline::ReadPopulationFolder(flags.population));
  ASSIGN_OR_RETURN(const pipeline::MeasurementModel model,
                   pipeline::MeasurementModel::Build(basis));
  std::vector<core::Mesh> avatars;
  for (Eigen::Index i = 0; i < population.samples.cols(); ++i) {
    core::Mesh avatar;
    avatar.positions =
        Eigen::Map<const core::Positions>(population.samples.col(i).data(), body::kBodyVertexCount, 3);
    avatar.faces = population.faces;
    avatars.push_back(std::move(avatar));
  }
  ASSIGN_OR_RETURN(const std::string table,
                   pipeline::EvaluateAvatarFromMeasurements(basis, model, avatars));
  std::cout << table;
  return absl::OkStatus();
}

}  // namespace

absl::Status RunPublish(const BasisFlags& flags) {
  v1::PublishAvatarBasisRequest request;
  request.set_population(flags.population_name);
  if (!flags.basis.empty()) {
    RETURN_IF_ERROR(proto::ReadMessageFile(flags.basis, request.mutable_basis()));
  } else if (!flags.preset.empty()) {
    v1::PopulationSpec& spec = *request.mutable_spec();
    spec.set_preset(flags.preset);
    spec.set_count(flags.count);
    spec.set_seed(flags.seed);
    if (flags.components > 0) {
      spec.mutable_selection()->set_component_count(static_cast<uint32_t>(flags.components));
    }
  } else {
    return absl::InvalidArgumentError("give --basis FILE or --preset to sample on the server");
  }
  auto stub = v1::Catalog::NewStub(rpc::OpenChannel(flags.remote.address));
  ASSIGN_OR_RETURN(std::unique_ptr<grpc::ClientContext> context,
                   NewCallContext(flags.remote, absl::Seconds(flags.remote.timeout_seconds)));
  v1::PublishAvatarBasisResponse response;
  RETURN_IF_ERROR(rpc::FromGrpcStatus(stub->PublishAvatarBasis(context.get(), request, &response)));
  std::cout << "avatar basis " << response.avatar_basis_id() << " (" << response.component_count()
            << " components) serves population " << flags.population_name << "\n";
  return absl::OkStatus();
}

void AddBasisCommands(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<BasisFlags>();
  CLI::App* basis = app.add_subcommand("basis", "The PCA avatar basis");
  basis->require_subcommand(1);

  CLI::App* build = basis->add_subcommand("build", "Build a basis from a population folder");
  build->add_option("--population", flags->population, "Population folder")->required();
  build->add_option("--max-error-mm", flags->max_error_mm,
                    "Keep the fewest components whose mean per-vertex training error is at "
                    "most this (default: 1 mm)");
  build->add_option("--components", flags->components, "Keep exactly this many components");
  build->add_option("--variance", flags->variance,
                    "Keep the fewest components explaining this share of variance (0, 1]");
  build->add_option("--out", flags->out, "Output basis file (.fbb)")->required();
  build->callback([&context, flags, build] {
    context.action = [flags, build] { return RunBuild(*flags, *build); };
  });

  CLI::App* info = basis->add_subcommand("info", "Print a basis: id, components, variance");
  info->add_option("basis", flags->basis, "Basis file (.fbb)")->required();
  info->callback([&context, flags] { context.action = [flags] { return RunInfo(*flags); }; });

  CLI::App* project = basis->add_subcommand(
      "project", "Project an avatar: weights and reconstruction error");
  project->add_option("--basis", flags->basis, "Basis file (.fbb)")->required();
  project->add_option("--avatar", flags->avatar, "Avatar OBJ (meters)")->required();
  project->add_flag("--json", flags->json,
                    "Print JSON with keys weights, mean_error_mm, max_error_mm, basis_id");
  project->callback(
      [&context, flags] { context.action = [flags] { return RunProject(*flags); }; });

  CLI::App* example = basis->add_subcommand(
      "example", "Write the example avatar mean + sigma * sigma_k * component_k");
  example->add_option("--basis", flags->basis, "Basis file (.fbb)")->required();
  example->add_option("--component", flags->component, "Component index k, from 0")->required();
  example->add_option("--sigma", flags->sigma, "Multiple of the component's standard deviation");
  example->add_option("--out", flags->out, "Output OBJ")->required();
  example->callback(
      [&context, flags] { context.action = [flags] { return RunExample(*flags); }; });

  CLI::App* eval = basis->add_subcommand(
      "eval", "Reconstruction error of every avatar of a (held-out) population folder");
  eval->add_option("--basis", flags->basis, "Basis file (.fbb)")->required();
  eval->add_option("--population", flags->population, "Population folder")->required();
  eval->callback([&context, flags] { context.action = [flags] { return RunEval(*flags); }; });

  CLI::App* eval_measurements = basis->add_subcommand(
      "eval-measurements",
      "Avatars from measurements: every avatar of a (held-out) population folder measured and "
      "fed back with three input sets; reproduction and surface error");
  eval_measurements->add_option("--basis", flags->basis, "Basis file (.fbb)")->required();
  eval_measurements->add_option("--population", flags->population, "Population folder")
      ->required();
  eval_measurements->callback(
      [&context, flags] { context.action = [flags] { return RunEvalMeasurements(*flags); }; });

  CLI::App* publish = basis->add_subcommand(
      "publish", "Make a basis the tenant's current one for a population, on the coordinator");
  AddRemoteOptions(publish, flags->remote);
  publish->add_option("--population", flags->population_name, "Population name (\"women\")")
      ->required();
  auto* file = publish->add_option("--basis", flags->basis, "A basis file (.fbb) to upload");
  auto* preset = publish->add_option("--preset", flags->preset,
                                     "Or sample on the server: women, men or all");
  file->excludes(preset);
  publish->add_option("--count", flags->count, "Server sampling: avatars (default 300)");
  publish->add_option("--seed", flags->seed, "Server sampling: seed (default 1)");
  publish->add_option("--components", flags->components,
                      "Server sampling: exactly this many components (default: 1 mm error)");
  publish->callback(
      [&context, flags] { context.action = [flags] { return RunPublish(*flags); }; });
}

}  // namespace fitbase::cli
