#include "pipeline/avatar_file.h"

#include "absl/strings/str_cat.h"
#include "body/body_model.h"
#include "core/garment_obj.h"
#include "core/obj_io.h"
#include "core/status_macros.h"

namespace fitbase::pipeline {
namespace {

// Adult heights, meters, with a wide margin: anything outside is a unit or file mix-up.
constexpr double kMinBodyHeight = 1.0;
constexpr double kMaxBodyHeight = 2.6;

absl::StatusOr<core::Mesh> CheckAvatar(core::Mesh mesh, absl::string_view name) {
  if (mesh.vertex_count() != body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat(
        name, " has ", mesh.vertex_count(), " vertices; a ", body::kBodyTopologyId,
        " avatar has ", body::kBodyVertexCount));
  }
  const double height = mesh.positions.col(1).maxCoeff() - mesh.positions.col(1).minCoeff();
  if (height < kMinBodyHeight || height > kMaxBodyHeight) {
    return absl::InvalidArgumentError(absl::StrCat(
        name, " is ", height, " units tall; avatars are in meters (expected ",
        kMinBodyHeight, " to ", kMaxBodyHeight, ")"));
  }
  mesh.topology_id = std::string(body::kBodyTopologyId);
  return mesh;
}

}  // namespace

absl::StatusOr<core::Mesh> ReadAvatarObj(const std::filesystem::path& path) {
  ASSIGN_OR_RETURN(core::Mesh mesh, core::ReadObj(path));
  return CheckAvatar(std::move(mesh), path.string());
}

absl::StatusOr<core::Mesh> ParseAvatarObj(absl::string_view text, absl::string_view name) {
  ASSIGN_OR_RETURN(core::GarmentMesh parsed, core::ParseGarmentObj(text, name));
  return CheckAvatar(std::move(parsed.mesh), name);
}

}  // namespace fitbase::pipeline
