#include "services/garment_importer.h"

#include <array>

#include "absl/strings/str_cat.h"
#include "core/body_skeleton.h"
#include "core/content_hash.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/mhclo_binding.h"
#include "core/status_macros.h"
#include "proto/avatar_params_codec.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "workers/garment_template.h"

namespace fitbase::services {
namespace {

// Bump when import changes what a given source produces.
constexpr absl::string_view kImportVersion = "fitbase-garment-import-v1";
// A garment placed on a body in meters fits in this box.
constexpr double kMaxGarmentExtent = 3.0;

struct SizeName {
  absl::string_view name;
  int step;
};
constexpr std::array<SizeName, 8> kSizeLadder = {{{"XXS", -3},
                                                  {"XS", -2},
                                                  {"S", -1},
                                                  {"M", 0},
                                                  {"L", 1},
                                                  {"XL", 2},
                                                  {"XXL", 3},
                                                  {"3XL", 4}}};

}  // namespace

absl::StatusOr<int> GradingStep(absl::string_view size) {
  for (const SizeName& s : kSizeLadder) {
    if (s.name == size) return s.step;
  }
  return absl::NotFoundError(
      absl::StrCat("unknown size '", size, "'; graded sizes are XXS, XS, S, M, L, XL, XXL, 3XL "
                   "(other names need a size mesh)"));
}

absl::StatusOr<core::Mesh> MeanFullAvatar(const core::BodyModel& model,
                                          const v1::AvatarBasis& basis) {
  const auto& params = basis.population().params();
  if (params.empty()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "avatar basis ", basis.id(), " has no avatar parameters; garments need a basis built "
        "from a `fitbase population` folder"));
  }
  core::Mesh mean;
  for (const v1::AvatarParams& p : params) {
    ASSIGN_OR_RETURN(core::BodyParams body_params, proto::BodyParamsFromProto(p));
    ASSIGN_OR_RETURN(core::Mesh full, model.BuildFullMesh(body_params));
    if (mean.positions.size() == 0) {
      mean = std::move(full);
    } else {
      mean.positions += full.positions;
    }
  }
  mean.positions /= static_cast<double>(params.size());
  return mean;
}

absl::StatusOr<v1::Garment> ImportGarment(const core::BodyModel& model,
                                          const v1::AvatarBasis& basis,
                                          const GarmentImportRequest& request) {
  if (request.mhclo.empty() == request.obj.empty()) {
    return absl::InvalidArgumentError("give exactly one of --mhclo and --obj");
  }
  if (request.sizes.empty()) return absl::InvalidArgumentError("a garment needs at least one size");
  ASSIGN_OR_RETURN(core::Mesh mean_full, MeanFullAvatar(model, basis));
  const core::Positions mean_body = mean_full.positions.topRows(core::kBodyVertexCount);

  v1::Garment garment;
  core::ContentHash id;
  id.Add(kImportVersion).Add(basis.id());
  core::GarmentMesh source;
  core::Positions placed;
  core::Positions rest;
  if (!request.mhclo.empty()) {
    ASSIGN_OR_RETURN(core::MhcloBinding binding, core::ReadMhclo(request.mhclo, core::kFullVertexCount));
    const std::filesystem::path obj_path = request.mhclo.parent_path() / binding.obj_file;
    ASSIGN_OR_RETURN(source, core::ReadGarmentObj(obj_path));
    if (source.mesh.vertex_count() != binding.vertex_count()) {
      return absl::InvalidArgumentError(absl::StrCat(
          obj_path.string(), " has ", source.mesh.vertex_count(), " vertices but its binding ",
          request.mhclo.string(), " binds ", binding.vertex_count()));
    }
    placed = core::ApplyMhclo(binding, mean_full.positions);
    rest = core::kMetersPerDataUnit * source.mesh.positions;
    *garment.mutable_binding() = proto::MhcloBindingToProto(binding);
    garment.set_name(request.name.empty() ? request.mhclo.stem().string() : request.name);
    garment.mutable_source()->set_kind("mhclo");
    garment.mutable_source()->set_path(request.mhclo.string());
    ASSIGN_OR_RETURN(std::string mhclo_bytes, core::ReadFileToString(request.mhclo));
    ASSIGN_OR_RETURN(std::string obj_bytes, core::ReadFileToString(obj_path));
    garment.mutable_source()->set_sha256(core::ContentHash().Add(obj_bytes).Add(mhclo_bytes).HexDigest());
  } else {
    ASSIGN_OR_RETURN(source, core::ReadGarmentObj(request.obj));
    placed = source.mesh.positions;
    rest = placed;
    const Eigen::RowVector3d extent = placed.colwise().maxCoeff() - placed.colwise().minCoeff();
    if (extent.maxCoeff() > kMaxGarmentExtent) {
      return absl::InvalidArgumentError(absl::StrCat(
          request.obj.string(), " spans ", extent.maxCoeff(),
          " units; a garment placed on the mean avatar is given in meters"));
    }
    garment.set_name(request.name.empty() ? request.obj.stem().string() : request.name);
    garment.mutable_source()->set_kind("obj");
    garment.mutable_source()->set_path(request.obj.string());
    ASSIGN_OR_RETURN(std::string obj_bytes, core::ReadFileToString(request.obj));
    garment.mutable_source()->set_sha256(core::ContentHash().Add(obj_bytes).HexDigest());
  }
  id.Add(garment.source().sha256());

  ASSIGN_OR_RETURN(core::Positions template_positions,
                   workers::FitTemplateToBody(placed, rest, source.mesh.faces, mean_body,
                                              core::Triangulate(model.body_faces())));
  source.mesh.topology_id = absl::StrCat("garment-", garment.name());
  source.mesh.positions = rest;
  *garment.mutable_rest_mesh() = proto::MeshToProto(source.mesh);
  source.mesh.positions = template_positions;
  *garment.mutable_template_mesh() = proto::MeshToProto(source.mesh);
  for (Eigen::Index i = 0; i < source.texcoords.size(); ++i) {
    garment.add_texcoords(static_cast<float>(source.texcoords.data()[i]));
  }
  garment.mutable_face_texcoord_indices()->Assign(source.face_texcoord_indices.begin(),
                                                  source.face_texcoord_indices.end());
  *garment.mutable_mean_avatar() = proto::MeshToProto(mean_full);
  garment.set_avatar_basis_id(basis.id());

  ASSIGN_OR_RETURN(std::vector<core::Bone> bones, core::BodyBones(model, mean_full.positions));
  for (Eigen::Index v = 0; v < template_positions.rows(); ++v) {
    const core::Bone& bone = core::NearestBone(bones, template_positions.row(v).transpose());
    // Bones point down the limbs and up the spine; one sign for all keeps the axes of
    // neighbouring vertices on different bones from cancelling in GradedRestLengths.
    Eigen::Vector3d axis = (bone.end - bone.start).normalized();
    if (axis.y() < 0) axis = -axis;
    for (int k = 0; k < 3; ++k) garment.add_length_axes(static_cast<float>(axis(k)));
    garment.add_vertex_regions(static_cast<uint32_t>(bone.region));
  }

  for (const std::string& size : request.sizes) {
    v1::GarmentSize* s = garment.add_sizes();
    s->set_name(size);
    const auto mesh_path = request.size_meshes.find(size);
    if (mesh_path != request.size_meshes.end()) {
      ASSIGN_OR_RETURN(core::GarmentMesh size_mesh, core::ReadGarmentObj(mesh_path->second));
      if (size_mesh.mesh.vertex_count() != source.mesh.vertex_count() ||
          size_mesh.mesh.faces != source.mesh.faces) {
        return absl::InvalidArgumentError(absl::StrCat(
            "size ", size, " mesh ", mesh_path->second.string(),
            " does not have the garment's topology (", source.mesh.vertex_count(), " vertices)"));
      }
      size_mesh.mesh.topology_id = source.mesh.topology_id;
      *s->mutable_rest() = proto::MeshToProto(size_mesh.mesh);
      ASSIGN_OR_RETURN(std::string bytes, core::ReadFileToString(mesh_path->second));
      id.Add(size).Add(bytes);
    } else {
      ASSIGN_OR_RETURN(int step, GradingStep(size));
      s->set_grading_step(step);
      id.Add(size).Add(int64_t{step});
    }
  }
  for (const auto& [size, path] : request.size_meshes) {
    if (std::find(request.sizes.begin(), request.sizes.end(), size) == request.sizes.end()) {
      return absl::InvalidArgumentError(
          absl::StrCat("size mesh ", path.string(), " is for size ", size, ", not in --sizes"));
    }
  }
  garment.set_id(id.HexDigest());
  return garment;
}

}  // namespace fitbase::services
