#ifndef FITBASE_BODY_BODY_MODEL_H_
#define FITBASE_BODY_BODY_MODEL_H_

#include <filesystem>
#include <string>
#include "absl/strings/string_view.h"
#include <map>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "body/body_params.h"
#include "body/target_file.h"
#include "core/mesh.h"

namespace fitbase::body {

inline constexpr int64_t kFullVertexCount = 19158;  // hm08, with helper and joint geometry.
inline constexpr int64_t kBodyVertexCount = 13380;  // The `body` group: vertices 0..13379.
inline constexpr absl::string_view kFullTopologyId = "makehuman-hm08";
inline constexpr absl::string_view kBodyTopologyId = "makehuman-hm08-body";
// base.obj and the targets are in decimeters.
inline constexpr double kMetersPerDataUnit = 0.1;

// The body (skin) faces of the full hm08 faces: exactly those whose corners all lie in
// 0..kBodyVertexCount-1 (the `body` group), found without the OBJ group names that OpenMesh
// drops.
core::PolygonFaces BodyFacesOf(const core::PolygonFaces& full_faces);

// The MakeHuman body model: the hm08 reference mesh and every target the macro parameters
// and local modifiers can weight, loaded once, so that a new body costs one sparse pass.
class BodyModel {
 public:
  // Loads base.obj and targets/ from `data_dir` (data/makehuman). Every target a parameter
  // can name must exist and parse; the error names the file.
  static absl::StatusOr<BodyModel> Load(const std::filesystem::path& data_dir);

  // The whole 19,158-vertex mesh for `params`, meters: body, helpers (garments bind to
  // `helper-tights` and `helper-skirt`) and joints. Faces are those of base.obj.
  absl::StatusOr<core::Mesh> BuildFullMesh(const BodyParams& params) const;

  // The 13,380-vertex body (skin) avatar for `params`, meters, with the body group's faces.
  absl::StatusOr<core::Mesh> BuildBody(const BodyParams& params) const;

  // Body faces, shared by every avatar of topology kBodyTopologyId.
  const core::PolygonFaces& body_faces() const { return body_faces_; }
  // Faces of the whole hm08 mesh, in base.obj order.
  const core::PolygonFaces& full_faces() const { return full_faces_; }

  // The vertices of base.obj's group `name` (e.g. "joint-l-knee"), ascending; empty if the
  // group does not exist.
  std::vector<int32_t> GroupVertices(absl::string_view name) const;

 private:
  BodyModel() = default;
  // base + sum(weight * target), in data units (decimeters).
  absl::StatusOr<core::Positions> DeformedPositions(const BodyParams& params) const;

  core::Positions base_;
  core::PolygonFaces full_faces_;
  core::PolygonFaces body_faces_;
  std::unordered_map<std::string, Target> targets_;
  std::map<std::string, std::vector<int32_t>, std::less<>> groups_;
};

}  // namespace fitbase::body

#endif  // FITBASE_BODY_BODY_MODEL_H_
