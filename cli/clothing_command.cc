// fitbase clothing build / fitbase fit: a garment size's clothing basis, and the online fit.
#include <chrono>
#include <iostream>
#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "cli/cli_context.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/kernel_ridge.h"
#include "core/obj_io.h"
#include "core/status_macros.h"
#include "pipeline/avatar_file.h"
#include "pipeline/avatar_projection.h"
#include "pipeline/clothing_basis_builder.h"
#include "pipeline/drape_runner.h"
#include "proto/clothing_basis_codec.h"
#include "proto/json_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"

namespace fitbase::cli {
namespace {

struct ClothingFlags {
  std::string basis;
  std::string garment;
  std::string size = "M";
  std::string method = "linear";
  double scale = 1.0;
  int samples = 0;
  uint64_t sample_seed = 1;
  int jobs = 2;
  std::string cache;
  workers::DrapeSchedule schedule;
  std::string out;
};

absl::Status RunClothingBuild(const ClothingFlags& flags) {
  ASSIGN_OR_RETURN(clothing::ClothingMethod method, clothing::ParseClothingMethod(flags.method));
  v1::AvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.basis, &basis));
  v1::Garment garment;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.garment, &garment));
  if (method == clothing::ClothingMethod::kKernel && flags.samples == 0) {
    return absl::InvalidArgumentError("--method kernel learns from sampled drapes; give --samples");
  }
  pipeline::ClothingBuildSpec spec{
      .avatar_basis = &basis,
      .garment = &garment,
      .size = flags.size,
      .example_scale = flags.scale,
      .sampled_drapes = method == clothing::ClothingMethod::kKernel ? flags.samples : 0,
      .sample_seed = flags.sample_seed,
      .settings = {},
      .schedule = flags.schedule,
      .model_threads = flags.jobs};
  ASSIGN_OR_RETURN(pipeline::ClothingPlan plan, pipeline::PlanClothingBasis(spec));
  std::vector<const workers::DrapeTask*> tasks;
  for (const workers::DrapeTask& task : plan.tasks) tasks.push_back(&task);
  ASSIGN_OR_RETURN(std::vector<v1::DrapeResult> results,
                   pipeline::RunDrapeTasks(tasks, {.cache_dir = flags.cache, .jobs = flags.jobs,
                                         .label = "drapes"}));
  ASSIGN_OR_RETURN(v1::ClothingBasis clothing,
                   pipeline::AssembleClothingBasis(spec, plan, method, results));
  RETURN_IF_ERROR(proto::WriteMessageFile(flags.out, clothing));
  int overstretched = 0;
  for (const v1::DrapeResult& r : results) overstretched += r.report().overstretched();
  std::cout << absl::StrFormat(
      "clothing basis %.12s: %s size %s, method %s, %d components, %d drapes (%d "
      "flagged overstretched), %d vertices\n",
      clothing.id(), garment.name(), flags.size, clothing.method(), clothing.component_count(),
      results.size(), overstretched, clothing.vertex_count());
  if (clothing.has_kernel()) {
    const v1::KernelCorrection& k = clothing.kernel();
    std::cout << absl::StrFormat(
        "kernel correction: %d outputs over %d bodies (%s kernel, %s scaling, ridge %g) of a "
        "linear part from %s; RMS miss per vertex on them %.2f mm linear, %.2f mm corrected "
        "(each body left out)\n",
        k.output_count(), k.center_count(),
        core::KernelShapeName(static_cast<core::KernelShape>(k.shape())), k.input_scaling(),
        k.ridge(), k.linear_part().empty() ? "axis" : k.linear_part(), k.linear_rms_mm(),
        k.loo_rms_mm());
    if (k.searched_bodies() > 0) {
      std::cout << absl::StrFormat(
          "kernel chosen on the first %d of the %d bodies (shape, scaling and reaches), then "
          "fitted to all\n",
          k.searched_bodies(), k.center_count());
    }
  }
  std::cout << "wrote " << flags.out << "\n";
  return absl::OkStatus();
}

struct FitFlags {
  std::string clothing;
  std::string avatar;
  std::string basis;
  std::string weights;
  bool no_cleanup = false;
  std::string fit_body = "weights";
  std::string out;
  std::string body_out;
};

// basis: loaded from --basis, if given.
absl::StatusOr<v1::AvatarWeights> CustomerWeights(
    const FitFlags& flags, const std::optional<pipeline::LoadedAvatarBasis>& basis) {
  v1::AvatarWeights weights;
  if (!flags.weights.empty()) {
    ASSIGN_OR_RETURN(std::string json, core::ReadFileToString(flags.weights));
    RETURN_IF_ERROR(proto::ParseJson(json, &weights));
    return weights;
  }
  if (!basis.has_value()) {
    return absl::InvalidArgumentError("--avatar needs --basis, the avatar basis to project onto");
  }
  ASSIGN_OR_RETURN(core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
  return pipeline::ProjectAvatar(*basis, avatar);
}

// The body the fit is made for and the service returns with it: mean + components x weights.
absl::Status WriteBodyOfWeights(const std::string& path, const pipeline::LoadedAvatarBasis& basis,
                                const v1::AvatarWeights& weights) {
  if (weights.basis_id() != basis.message.id()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "--body-out: the weights are on avatar basis '", weights.basis_id(), "'; --basis is ",
        basis.message.id()));
  }
  absl::StatusOr<Eigen::VectorXd> checked =
      pipeline::CheckedWeights(weights, basis.pca.components.cols(), basis.message.id());
  if (!checked.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("--body-out: ", checked.status().message()));
  }
  ASSIGN_OR_RETURN(core::Mesh body, proto::MeshFromProto(basis.message.mean()));
  body.positions = pipeline::BodyOfWeights(basis, *checked);
  return core::WriteObj(path, body);
}

absl::Status RunFit(const FitFlags& flags) {
  if (flags.avatar.empty() == flags.weights.empty()) {
    return absl::InvalidArgumentError("give exactly one of --avatar and --weights");
  }
  if (flags.fit_body == "own" && flags.avatar.empty()) {
    return absl::InvalidArgumentError("--fit-body own fits --avatar's mesh; give --avatar");
  }
  if (!flags.body_out.empty() && flags.basis.empty()) {
    return absl::InvalidArgumentError(
        "--body-out needs --basis, whose mean and components make the body");
  }
  v1::ClothingBasis clothing;
  RETURN_IF_ERROR(proto::ReadMessageFile(flags.clothing, &clothing));
  std::optional<pipeline::LoadedAvatarBasis> basis;
  if (!flags.basis.empty()) {
    ASSIGN_OR_RETURN(basis, pipeline::LoadAvatarBasis(flags.basis));
  }
  ASSIGN_OR_RETURN(v1::AvatarWeights weights, CustomerWeights(flags, basis));
  if (weights.basis_id() != clothing.avatar_basis_id()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "the weights are on avatar basis '", weights.basis_id(), "'; clothing basis ",
        clothing.id(), " takes weights on ", clothing.avatar_basis_id()));
  }
  ASSIGN_OR_RETURN(clothing::ClothingFitter fitter, proto::ClothingFitterFromProto(clothing));
  ASSIGN_OR_RETURN(core::GarmentMesh mesh, proto::GarmentMeshFromClothingBasis(clothing));
  const Eigen::VectorXf w =
      Eigen::Map<const Eigen::VectorXd>(weights.weights().data(), weights.weights_size())
          .cast<float>();
  std::vector<float> own_body;
  if (flags.fit_body == "own") {
    ASSIGN_OR_RETURN(const core::Mesh avatar, pipeline::ReadAvatarObj(flags.avatar));
    own_body = core::InterleavedFloats(avatar.positions);
  }
  clothing::FitScratch scratch;
  Eigen::VectorXf positions;
  const auto start = std::chrono::steady_clock::now();
  ASSIGN_OR_RETURN(int64_t moved,
                   own_body.empty()
                       ? fitter.Fit(w, !flags.no_cleanup, scratch, positions)
                       : fitter.FitToBody(w, own_body, !flags.no_cleanup, scratch, positions));
  const double micros =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  mesh.mesh.positions =
      Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          positions.data(), mesh.mesh.vertex_count(), 3)
          .cast<double>();
  RETURN_IF_ERROR(core::WriteGarmentObj(flags.out, mesh));
  if (!flags.body_out.empty()) {
    RETURN_IF_ERROR(WriteBodyOfWeights(flags.body_out, *basis, weights));
    std::cout << absl::StrFormat("wrote %s (the body of the weights)\n", flags.body_out);
  }
  std::cout << absl::StrFormat(
      "fit %s size %s (%s, %d weights, avatar reconstruction error %.2f mm) to %s: %.0f us, "
      "clean-up %s (%d vertices pushed out)\nwrote %s\n",
      clothing.garment_id().substr(0, 12), clothing.size(), clothing.method(),
      weights.weights_size(), weights.mean_error_mm(),
      own_body.empty() ? "the body of the weights" : "the avatar's own mesh", micros,
      flags.no_cleanup ? "off" : "on", moved, flags.out);
  return absl::OkStatus();
}

}  // namespace

void AddClothingCommands(CLI::App& app, CliContext& context) {
  auto flags = std::make_shared<ClothingFlags>();
  CLI::App* clothing = app.add_subcommand("clothing", "Clothing bases: a garment size's fit model");
  clothing->require_subcommand(1);
  CLI::App* build = clothing->add_subcommand(
      "build", "Drape a garment size onto the 2N + 1 example avatars (and, for kernel, sampled bodies) "
      "and build its clothing basis");
  build->add_option("--basis", flags->basis, "Avatar basis (.fbb)")->required();
  build->add_option("--garment", flags->garment, "Garment imported on that basis (.fbg)")
      ->required();
  build->add_option("--size", flags->size, "Size name (default: M)");
  build->add_option("--method", flags->method,
                    "paper, linear (default), quadratic or kernel (needs --samples)");
  build->add_option("--samples", flags->samples,
                    "Bodies sampled from the basis's population and draped, which kernel learns "
                    "from (default: 0)")
      ->check(CLI::Range(0, pipeline::kMaxSampledDrapes));
  build->add_option("--sample-seed", flags->sample_seed, "Seed of the sampled bodies (default: 1)");
  build->add_option("--scale", flags->scale,
                    "Examples at mean +- scale x sigma_k along each component (default: 1)")
      ->check(CLI::PositiveNumber);
  build
      ->add_option("--jobs", flags->jobs,
                   "Drapes side by side, and threads of the kernel model's search (default: 2)")
      ->check(CLI::Range(1, 256));
  build->add_option("--cache", flags->cache, "Folder of drape results reused by content key");
  AddDrapeScheduleOptions(build, flags->schedule);
  build->add_option("--out", flags->out, "Output clothing basis (.fbc)")->required();
  build->callback([&context, flags] {
    context.action = [flags] { return RunClothingBuild(*flags); };
  });

  auto fit_flags = std::make_shared<FitFlags>();
  CLI::App* fit =
      app.add_subcommand("fit", "Fit a garment size to a customer from its clothing basis");
  fit->add_option("--clothing", fit_flags->clothing, "Clothing basis (.fbc)")->required();
  fit->add_option("--avatar", fit_flags->avatar, "Customer body avatar OBJ (meters)");
  fit->add_option("--basis", fit_flags->basis, "Avatar basis to project --avatar onto (.fbb)");
  fit->add_option("--weights", fit_flags->weights,
                  "Customer weights as JSON (`fitbase basis project --json`)");
  fit->add_flag("--no-cleanup", fit_flags->no_cleanup,
                "Skip pushing vertices out of the customer's body");
  fit->add_option("--fit-body", fit_flags->fit_body,
                  "The body the garment is fitted to: weights (the body of the weights, mean + "
                  "components x weights) or own (--avatar's own mesh: the fit follows what the "
                  "projection left out, and the clean-up clears the mesh) (default: weights)")
      ->check(CLI::IsMember({"own", "weights"}));
  fit->add_option("--body-out", fit_flags->body_out,
                  "Also write the body the fit is made for, mean + components x weights (the "
                  "body the fit service returns), as an OBJ; needs --basis");
  fit->add_option("--out", fit_flags->out, "Fitted garment OBJ (the garment's vertex order)")
      ->required();
  fit->callback([&context, fit_flags] {
    context.action = [fit_flags] { return RunFit(*fit_flags); };
  });
}

}  // namespace fitbase::cli
