#include "pipeline/garment_importer.h"

#include <algorithm>
#include <array>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "body/body_skeleton.h"
#include "clothing/size_advice.h"
#include "core/content_hash.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/mhclo_binding.h"
#include "core/status_macros.h"
#include "proto/avatar_params_codec.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"
#include "workers/cloth_solver.h"
#include "workers/garment_template.h"

namespace fitbase::pipeline {
namespace {

// Bump when import changes what a given source produces.
constexpr absl::string_view kImportVersion = "fitbase-garment-import-v10";
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

absl::StatusOr<core::Mesh> MeanFullAvatar(const body::BodyModel& model,
                                          const v1::AvatarBasis& basis) {
  const auto& params = basis.population().params();
  if (params.empty()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "avatar basis ", basis.id(), " has no avatar parameters; garments need a basis built "
        "from a `fitbase population` folder"));
  }
  core::Mesh mean;
  for (const v1::AvatarParams& p : params) {
    ASSIGN_OR_RETURN(body::BodyParams body_params, proto::BodyParamsFromProto(p));
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

absl::StatusOr<GarmentImportRequest> ReadGarmentImportFiles(const GarmentImportPaths& paths) {
  if (paths.mhclo.empty() == paths.obj.empty()) {
    return absl::InvalidArgumentError("give exactly one of --mhclo and --obj");
  }
  GarmentImportRequest request;
  std::filesystem::path obj_path = paths.obj;
  if (!paths.mhclo.empty()) {
    SourceFile& mhclo = request.mhclo.emplace();
    mhclo.name = paths.mhclo.string();
    ASSIGN_OR_RETURN(mhclo.bytes, core::ReadFileToString(paths.mhclo));
    // Parsed whole, so a bad binding is reported as such rather than as a missing OBJ.
    ASSIGN_OR_RETURN(core::MhcloBinding binding,
                     core::ParseMhclo(mhclo.bytes, body::kFullVertexCount, mhclo.name));
    if (binding.obj_file.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(mhclo.name, " names no obj_file"));
    }
    obj_path = paths.mhclo.parent_path() / binding.obj_file;
  }
  request.obj.name = obj_path.string();
  ASSIGN_OR_RETURN(request.obj.bytes, core::ReadFileToString(obj_path));
  for (const auto& [size, path] : paths.size_meshes) {
    SourceFile& mesh = request.size_meshes[size];
    mesh.name = path.string();
    ASSIGN_OR_RETURN(mesh.bytes, core::ReadFileToString(path));
  }
  return request;
}

std::string SourceSha256(const GarmentImportRequest& request) {
  core::ContentHash hash;
  hash.Add(request.obj.bytes);
  if (request.mhclo.has_value()) hash.Add(request.mhclo->bytes);
  return hash.HexDigest();
}

absl::StatusOr<v1::ElasticCuffs> ParseCuffs(absl::string_view list) {
  v1::ElasticCuffs cuffs;
  std::vector<std::string> seen;
  for (absl::string_view word : absl::StrSplit(list, ',', absl::SkipWhitespace())) {
    word = absl::StripAsciiWhitespace(word);
    if (std::find(seen.begin(), seen.end(), word) != seen.end()) {
      return absl::InvalidArgumentError(absl::StrCat("cuffs '", list, "' name ", word, " twice"));
    }
    seen.emplace_back(word);
    if (word == "sleeves") {
      cuffs.set_sleeves(true);
    } else if (word == "legs") {
      cuffs.set_legs(true);
    } else if (word != "none") {
      return absl::InvalidArgumentError(
          absl::StrCat("cuffs '", list, "': '", word, "' is not sleeves, legs or none"));
    }
  }
  if (std::find(seen.begin(), seen.end(), "none") != seen.end() && seen.size() > 1) {
    return absl::InvalidArgumentError(absl::StrCat("cuffs '", list, "' name none and cuffs"));
  }
  return cuffs;
}

bool DeclaresCuffs(const v1::ElasticCuffs& cuffs) { return cuffs.sleeves() || cuffs.legs(); }

absl::StatusOr<std::string> GarmentImportId(absl::string_view basis_id,
                                            const GarmentImportRequest& request) {
  core::ContentHash id;
  // The template fit runs the cloth solver, so a solver that changes its results changes
  // every import (a cache keyed without it served templates of an older solver).
  id.Add(kImportVersion).Add(workers::kSimulatorVersion);
  id.Add(basis_id).Add(SourceSha256(request));
  for (const std::string& size : request.sizes) {
    const auto mesh_file = request.size_meshes.find(size);
    if (mesh_file != request.size_meshes.end()) {
      id.Add(size).Add(mesh_file->second.bytes);
    } else {
      ASSIGN_OR_RETURN(int step, GradingStep(size));
      id.Add(size).Add(int64_t{step});
    }
  }
  if (DeclaresCuffs(request.cuffs)) {
    id.Add("cuffs").Add(int64_t{request.cuffs.sleeves()}).Add(int64_t{request.cuffs.legs()});
  }
  return id.HexDigest();
}

absl::StatusOr<v1::Garment> ImportGarment(const body::BodyModel& model,
                                          const v1::AvatarBasis& basis,
                                          const GarmentImportRequest& request) {
  // Checked before any parsing or fitting, so a bad request fails at once.
  if (request.sizes.empty()) return absl::InvalidArgumentError("a garment needs at least one size");
  if (!request.garment_type.empty()) {
    RETURN_IF_ERROR(clothing::ParseGarmentType(request.garment_type).status());
  }
  for (const auto& [size, file] : request.size_meshes) {
    if (std::find(request.sizes.begin(), request.sizes.end(), size) == request.sizes.end()) {
      return absl::InvalidArgumentError(absl::StrCat("size mesh ", file.name, " is for size ",
                                                     size, ", not one of the sizes ",
                                                     absl::StrJoin(request.sizes, ",")));
    }
  }

  v1::Garment garment;
  core::MhcloBinding binding;
  if (request.mhclo.has_value()) {
    ASSIGN_OR_RETURN(binding, core::ParseMhclo(request.mhclo->bytes, body::kFullVertexCount,
                                               request.mhclo->name));
  }
  ASSIGN_OR_RETURN(core::GarmentMesh source,
                   core::ParseGarmentObj(request.obj.bytes, request.obj.name));
  core::Positions rest;
  if (request.mhclo.has_value()) {
    if (source.mesh.vertex_count() != binding.vertex_count()) {
      return absl::InvalidArgumentError(absl::StrCat(
          request.obj.name, " has ", source.mesh.vertex_count(), " vertices but its binding ",
          request.mhclo->name, " binds ", binding.vertex_count()));
    }
    rest = body::kMetersPerDataUnit * source.mesh.positions;
    *garment.mutable_binding() = proto::MhcloBindingToProto(binding);
    garment.mutable_source()->set_kind("mhclo");
  } else {
    rest = source.mesh.positions;
    const Eigen::RowVector3d extent = rest.colwise().maxCoeff() - rest.colwise().minCoeff();
    if (extent.maxCoeff() > kMaxGarmentExtent) {
      return absl::InvalidArgumentError(absl::StrCat(
          request.obj.name, " spans ", extent.maxCoeff(),
          " units; a garment placed on the mean avatar is given in meters"));
    }
    garment.mutable_source()->set_kind("obj");
  }
  const std::string& source_name = request.mhclo.has_value() ? request.mhclo->name
                                                             : request.obj.name;
  garment.mutable_source()->set_path(source_name);
  garment.set_name(request.name.empty() ? std::filesystem::path(source_name).stem().string()
                                        : request.name);
  if (garment.name().empty()) {
    return absl::InvalidArgumentError("the garment has no name: give one, or name its file");
  }
  source.mesh.topology_id = absl::StrCat("garment-", garment.name());

  garment.mutable_source()->set_sha256(SourceSha256(request));
  ASSIGN_OR_RETURN(std::string id, GarmentImportId(basis.id(), request));
  garment.set_id(std::move(id));
  garment.set_garment_type(request.garment_type);
  if (DeclaresCuffs(request.cuffs)) *garment.mutable_cuffs() = request.cuffs;
  for (const std::string& size : request.sizes) {
    v1::GarmentSize* s = garment.add_sizes();
    s->set_name(size);
    const auto mesh_file = request.size_meshes.find(size);
    if (mesh_file != request.size_meshes.end()) {
      const SourceFile& file = mesh_file->second;
      ASSIGN_OR_RETURN(core::GarmentMesh size_mesh, core::ParseGarmentObj(file.bytes, file.name));
      if (size_mesh.mesh.vertex_count() != source.mesh.vertex_count() ||
          size_mesh.mesh.faces != source.mesh.faces) {
        return absl::InvalidArgumentError(absl::StrCat(
            "size ", size, " mesh ", file.name, " does not have the garment's topology (",
            source.mesh.vertex_count(), " vertices)"));
      }
      size_mesh.mesh.topology_id = source.mesh.topology_id;
      *s->mutable_rest() = proto::MeshToProto(size_mesh.mesh);
    } else {
      ASSIGN_OR_RETURN(int step, GradingStep(size));
      s->set_grading_step(step);
    }
  }

  ASSIGN_OR_RETURN(core::Mesh mean_full, MeanFullAvatar(model, basis));
  const core::Positions mean_body = mean_full.positions.topRows(body::kBodyVertexCount);
  const core::Positions placed =
      request.mhclo.has_value() ? core::ApplyMhclo(binding, mean_full.positions) : rest;
  ASSIGN_OR_RETURN(core::Positions template_positions,
                   workers::FitTemplateToBody(placed, rest, source.mesh.faces, mean_body,
                                              core::Triangulate(model.body_faces())));
  source.mesh.positions = template_positions;
  *garment.mutable_template_mesh() = proto::MeshToProto(source.mesh);
  for (Eigen::Index i = 0; i < source.texcoords.size(); ++i) {
    garment.add_texcoords(static_cast<float>(source.texcoords.data()[i]));
  }
  garment.mutable_face_texcoord_indices()->Assign(source.face_texcoord_indices.begin(),
                                                  source.face_texcoord_indices.end());
  *garment.mutable_mean_avatar() = proto::MeshToProto(mean_full);
  garment.set_avatar_basis_id(basis.id());

  ASSIGN_OR_RETURN(std::vector<body::Bone> bones, body::BodyBones(model, mean_full.positions));
  for (Eigen::Index v = 0; v < template_positions.rows(); ++v) {
    const body::Bone& bone = body::NearestBone(bones, template_positions.row(v).transpose());
    // Bones point down the limbs and up the spine; one sign for all keeps the axes of
    // neighbouring vertices on different bones from cancelling in GradedRestLengths.
    Eigen::Vector3d axis = (bone.end - bone.start).normalized();
    if (axis.y() < 0) axis = -axis;
    for (int k = 0; k < 3; ++k) garment.add_length_axes(static_cast<float>(axis(k)));
    garment.add_vertex_regions(static_cast<uint32_t>(bone.region));
  }
  return garment;
}

}  // namespace fitbase::pipeline
