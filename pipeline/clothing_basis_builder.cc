#include "pipeline/clothing_basis_builder.h"

#include "absl/strings/str_cat.h"
#include "clothing/body_correspondence.h"
#include "core/content_hash.h"
#include "core/random.h"
#include "core/status_macros.h"
#include "proto/avatar_basis_codec.h"
#include "proto/clothing_basis_codec.h"
#include "proto/mesh_codec.h"
#include "workers/garment_drape.h"

namespace fitbase::pipeline {
namespace {

// Part of every clothing basis id: a basis assembled by other code (another model or clean-up)
// from the same drapes is other bytes, so it must have another id. Version 2: the kernel
// method and the clean-up's triangle guards. Version 3: the body under the garment
// (BodyCorrespondence::body_triangles), which the clean-up's deep pushes ask. Version 4: the
// kernel's linear part fitted by least squares with enough training bodies. Version 5: the
// relevance search from 5 training bodies per component (clothing::kRelevanceBodiesPerComponent)
// instead of 10. (A kernel searched on fewer than all its bodies adds that count instead of a
// version.)
constexpr absl::string_view kAssemblyVersion = "clothing-basis-5";

}  // namespace

std::string ClothingPlan::TaskLabel(size_t task) const {
  const auto examples = static_cast<size_t>(design.example_count());
  return task < examples ? design.Label(static_cast<int>(task))
                         : absl::StrCat("sample-", task - examples);
}

Eigen::VectorXd ClothingPlan::TaskWeights(size_t task) const {
  const auto examples = static_cast<size_t>(design.example_count());
  if (task < examples) return design.Weights(static_cast<int>(task));
  return sample_weights.col(static_cast<Eigen::Index>(task - examples));
}

absl::StatusOr<ClothingPlan> PlanClothingBasis(const ClothingBuildSpec& spec) {
  const v1::AvatarBasis& basis = *spec.avatar_basis;
  const v1::Garment& garment = *spec.garment;
  if (garment.avatar_basis_id() != basis.id()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "garment ", garment.name(), " was imported on avatar basis ", garment.avatar_basis_id(),
        ", not on ", basis.id(), "; import it on this basis first"));
  }
  RETURN_IF_ERROR(workers::FindGarmentSize(garment, spec.size).status());
  if (spec.sampled_drapes < 0 || spec.sampled_drapes > kMaxSampledDrapes) {
    return absl::InvalidArgumentError(absl::StrCat("sampled drapes ", spec.sampled_drapes,
                                                   " is outside [0, ", kMaxSampledDrapes, "]"));
  }
  ClothingPlan plan;
  ASSIGN_OR_RETURN(plan.avatar, proto::PcaBasisFromProto(basis));
  ASSIGN_OR_RETURN(plan.design, clothing::MakeExampleDesign(plan.avatar.variances.cwiseSqrt(),
                                                            spec.example_scale));
  const int n = plan.design.component_count();
  plan.sample_weights.resize(n, spec.sampled_drapes);
  for (int i = 0; i < spec.sampled_drapes; ++i) {
    // One stream per sample, so a plan with more samples starts with the same bodies and
    // their drapes come from the cache.
    core::Random random(spec.sample_seed, static_cast<uint64_t>(i));
    for (int k = 0; k < n; ++k) {
      plan.sample_weights(k, i) = plan.design.sigmas(k) * random.TruncatedNormal(0, 1, -3, 3);
    }
  }
  auto add_task = [&](const Eigen::VectorXd& weights) {
    const Eigen::VectorXd body = core::ReconstructFromWeights(plan.avatar, weights);
    plan.tasks.push_back(workers::MakeDrapeTask(
        garment, spec.size, Eigen::Map<const core::Positions>(body.data(), body.size() / 3, 3),
        spec.settings, spec.schedule));
  };
  const auto task_count = static_cast<size_t>(plan.design.example_count() + spec.sampled_drapes);
  for (size_t task = 0; task < task_count; ++task) add_task(plan.TaskWeights(task));
  return plan;
}

absl::StatusOr<v1::ClothingBasis> AssembleClothingBasis(
    const ClothingBuildSpec& spec, const ClothingPlan& plan, clothing::ClothingMethod method,
    const std::vector<v1::DrapeResult>& results) {
  const v1::Garment& garment = *spec.garment;
  const int64_t vertex_count = garment.template_mesh().vertex_count();
  if (results.size() != plan.tasks.size()) {
    return absl::InvalidArgumentError(absl::StrCat("got ", results.size(), " drape results for ",
                                                   plan.tasks.size(), " drapes"));
  }
  const bool kernel = method == clothing::ClothingMethod::kKernel;
  const auto examples_used = static_cast<Eigen::Index>(plan.design.example_count());
  const Eigen::Index sampled = plan.sample_weights.cols();
  if (kernel && sampled == 0) {
    return absl::FailedPreconditionError(
        "the kernel method learns from drapes of sampled bodies; plan some (sampled drapes > 0)");
  }
  const Eigen::Index used = kernel ? examples_used + sampled : examples_used;
  Eigen::MatrixXd drapes(3 * vertex_count, used);
  for (Eigen::Index e = 0; e < used; ++e) {
    const auto task = static_cast<size_t>(e);
    if (results[task].key() != plan.tasks[task].key) {
      return absl::InvalidArgumentError(absl::StrCat("drape result ", results[task].key(),
                                                     " does not belong to drape ",
                                                     plan.TaskLabel(task)));
    }
    ASSIGN_OR_RETURN(core::Positions positions,
                     workers::DrapeResultPositions(results[task], vertex_count));
    drapes.col(e) = positions.reshaped<Eigen::RowMajor>();
  }
  clothing::ClothingModel model;
  clothing::KernelBuildReport kernel_report;
  if (kernel) {
    ASSIGN_OR_RETURN(
        model, clothing::BuildKernelClothingModel(plan.design, drapes.leftCols(examples_used),
                                                  {plan.sample_weights, drapes.rightCols(sampled)},
                                                  {.threads = spec.model_threads}, &kernel_report));
  } else {
    ASSIGN_OR_RETURN(model, clothing::BuildClothingModel(method, plan.design, drapes));
  }
  ASSIGN_OR_RETURN(core::Mesh mean_body, proto::MeshFromProto(spec.avatar_basis->mean()));
  std::vector<core::Positions> example_drapes;
  std::vector<clothing::CorrespondenceExample> examples;
  for (Eigen::Index e = 0; e < drapes.cols(); ++e) {
    example_drapes.push_back(
        Eigen::Map<const core::Positions>(drapes.col(e).data(), vertex_count, 3));
  }
  for (Eigen::Index e = 0; e < drapes.cols(); ++e) {
    examples.push_back({&example_drapes[e], plan.TaskWeights(static_cast<size_t>(e))});
  }
  ASSIGN_OR_RETURN(const core::Mesh garment_mesh, proto::MeshFromProto(garment.template_mesh()));
  ASSIGN_OR_RETURN(clothing::BodyCorrespondence correspondence,
                   clothing::BuildBodyCorrespondence(examples, plan.avatar,
                                                 core::Triangulate(mean_body.faces),
                                                 core::Triangulate(garment_mesh.faces),
                                                 spec.settings.collision_offset,
                                                 spec.cleanup_anchors));

  v1::ClothingBasis message;
  message.set_garment_id(garment.id());
  message.set_size(spec.size);
  message.set_avatar_basis_id(spec.avatar_basis->id());
  proto::ClothingModelToProto(model, &message);
  proto::BodyCorrespondenceToProto(correspondence, message.mutable_correspondence());
  v1::ClothingProvenance* provenance = message.mutable_provenance();
  provenance->set_example_scale(spec.example_scale);
  provenance->set_simulator(workers::SimulatorDescription(spec.settings, spec.schedule));
  core::ContentHash id;
  id.Add(kAssemblyVersion)
      .Add(absl::string_view(garment.id()))
      .Add(absl::string_view(spec.size))
      .Add(absl::string_view(spec.avatar_basis->id()))
      .Add(absl::string_view(message.method()))
      .Add(spec.example_scale)
      .Add(static_cast<int64_t>(spec.cleanup_anchors));
  for (Eigen::Index e = 0; e < used; ++e) {
    const auto task = static_cast<size_t>(e);
    v1::ClothingExample* example = provenance->add_examples();
    example->set_label(plan.TaskLabel(task));
    const Eigen::VectorXd weights = plan.TaskWeights(task);
    example->mutable_weights()->Assign(weights.begin(), weights.end());
    example->set_drape_key(plan.tasks[task].key);
    id.Add(absl::string_view(plan.tasks[task].key));
  }
  if (kernel) {
    provenance->set_sampled_drapes(static_cast<uint32_t>(sampled));
    provenance->set_sample_seed(spec.sample_seed);
    v1::KernelCorrection* k = message.mutable_kernel();
    k->set_input_scaling(kernel_report.input_scaling);
    k->set_linear_part(kernel_report.linear_part);
    k->set_ridge(kernel_report.ridge);
    k->set_linear_rms_mm(kernel_report.linear_rms_mm);
    k->set_loo_rms_mm(kernel_report.loo_rms_mm);
    // Only a search on fewer than all the bodies makes other bytes than before it, so only
    // that changes the id: bases of up to KernelBuildOptions::search_bodies keep theirs.
    if (kernel_report.searched_bodies < used) {
      k->set_searched_bodies(static_cast<uint32_t>(kernel_report.searched_bodies));
      id.Add(absl::string_view("searched-bodies")).Add(kernel_report.searched_bodies);
    }
  }
  message.set_id(id.HexDigest());
  v1::Mesh* faces = message.mutable_faces();
  *faces = garment.template_mesh();
  faces->clear_positions();
  *message.mutable_texcoords() = garment.texcoords();
  *message.mutable_face_texcoord_indices() = garment.face_texcoord_indices();
  return message;
}

}  // namespace fitbase::pipeline
