#include "body/body_model.h"

#include <algorithm>
#include <set>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "body/macro_weights.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/status_macros.h"

namespace fitbase::body {
namespace {

// The vertex sets of the OBJ's `g` groups, from the faces listed under each (OpenMesh keeps
// faces in file order but drops group names).
std::map<std::string, std::vector<int32_t>, std::less<>> GroupsOf(absl::string_view obj_text,
                                                                  const core::PolygonFaces& faces) {
  std::map<std::string, std::set<int32_t>, std::less<>> sets;
  std::string group;
  size_t face = 0;
  size_t corner = 0;
  for (absl::string_view line : absl::StrSplit(obj_text, '\n')) {
    if (absl::StartsWith(line, "g ")) {
      group = std::string(absl::StripAsciiWhitespace(line.substr(2)));
    } else if (absl::StartsWith(line, "f ") && face < faces.sizes.size()) {
      const int32_t size = faces.sizes[face++];
      sets[group].insert(faces.indices.begin() + static_cast<ptrdiff_t>(corner),
                         faces.indices.begin() + static_cast<ptrdiff_t>(corner + size));
      corner += static_cast<size_t>(size);
    }
  }
  std::map<std::string, std::vector<int32_t>, std::less<>> groups;
  for (auto& [name, vertices] : sets) groups[name].assign(vertices.begin(), vertices.end());
  return groups;
}

}  // namespace

core::PolygonFaces BodyFacesOf(const core::PolygonFaces& faces) {
  core::PolygonFaces body;
  size_t corner = 0;
  for (int32_t size : faces.sizes) {
    const auto first = faces.indices.begin() + static_cast<std::ptrdiff_t>(corner);
    corner += static_cast<size_t>(size);
    if (std::all_of(first, first + size, [](int32_t v) { return v < kBodyVertexCount; })) {
      body.sizes.push_back(size);
      body.indices.insert(body.indices.end(), first, first + size);
    }
  }
  return body;
}

std::vector<int32_t> BodyModel::GroupVertices(absl::string_view name) const {
  const auto it = groups_.find(name);
  return it == groups_.end() ? std::vector<int32_t>() : it->second;
}

absl::StatusOr<BodyModel> BodyModel::Load(const std::filesystem::path& data_dir) {
  BodyModel model;
  ASSIGN_OR_RETURN(core::Mesh base, core::ReadObj(data_dir / "base.obj"));
  if (base.vertex_count() != kFullVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat((data_dir / "base.obj").string(), " has ",
                                                   base.vertex_count(), " vertices, expected ",
                                                   kFullVertexCount, " (MakeHuman hm08)"));
  }
  model.base_ = std::move(base.positions);
  model.full_faces_ = std::move(base.faces);
  model.body_faces_ = BodyFacesOf(model.full_faces_);
  ASSIGN_OR_RETURN(std::string obj_text, core::ReadFileToString(data_dir / "base.obj"));
  model.groups_ = GroupsOf(obj_text, model.full_faces_);
  for (std::string& path : AllTargetPaths()) {
    ASSIGN_OR_RETURN(Target target,
                     ReadTargetFile(data_dir / "targets" / path, kFullVertexCount));
    model.targets_.emplace(std::move(path), std::move(target));
  }
  return model;
}

absl::StatusOr<core::Positions> BodyModel::DeformedPositions(const BodyParams& params) const {
  RETURN_IF_ERROR(ValidateBodyParams(params));
  core::Positions positions = base_;
  for (const TargetWeight& tw : ComputeTargetWeights(params)) {
    const Target& target = targets_.at(tw.path);
    // Raw rows: Eigen's 1x3 block expressions cost more than the arithmetic here.
    double* out = positions.data();
    const float* offset = target.offsets.data();
    for (const int32_t index : target.indices) {
      double* row = out + 3 * static_cast<ptrdiff_t>(index);
      row[0] += tw.weight * offset[0];
      row[1] += tw.weight * offset[1];
      row[2] += tw.weight * offset[2];
      offset += 3;
    }
  }
  return positions;
}

absl::StatusOr<core::Mesh> BodyModel::BuildFullMesh(const BodyParams& params) const {
  ASSIGN_OR_RETURN(core::Positions positions, DeformedPositions(params));
  return core::Mesh{.topology_id = std::string(kFullTopologyId),
              .positions = positions * kMetersPerDataUnit,
              .faces = full_faces_};
}

absl::StatusOr<core::Mesh> BodyModel::BuildBody(const BodyParams& params) const {
  ASSIGN_OR_RETURN(core::Positions positions, DeformedPositions(params));
  return core::Mesh{.topology_id = std::string(kBodyTopologyId),
              .positions = positions.topRows(kBodyVertexCount) * kMetersPerDataUnit,
              .faces = body_faces_};
}

}  // namespace fitbase::body
