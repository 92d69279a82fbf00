#include "body/body_skeleton.h"

#include <array>
#include <limits>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::body {
namespace {

struct BoneSpec {
  const char* from;
  const char* to;
  BodyRegion region;
};

// The joints a garment can cover, bottom of the spine to the neck and down each limb.
constexpr BoneSpec kBones[] = {
    {"joint-pelvis", "joint-spine-4", BodyRegion::kTorso},
    {"joint-spine-4", "joint-spine-3", BodyRegion::kTorso},
    {"joint-spine-3", "joint-spine-2", BodyRegion::kTorso},
    {"joint-spine-2", "joint-spine-1", BodyRegion::kTorso},
    {"joint-spine-1", "joint-neck", BodyRegion::kTorso},
    {"joint-neck", "joint-head", BodyRegion::kTorso},
    {"joint-l-clavicle", "joint-l-shoulder", BodyRegion::kArms},
    {"joint-l-shoulder", "joint-l-elbow", BodyRegion::kArms},
    {"joint-l-elbow", "joint-l-hand", BodyRegion::kArms},
    {"joint-r-clavicle", "joint-r-shoulder", BodyRegion::kArms},
    {"joint-r-shoulder", "joint-r-elbow", BodyRegion::kArms},
    {"joint-r-elbow", "joint-r-hand", BodyRegion::kArms},
    {"joint-l-upper-leg", "joint-l-knee", BodyRegion::kLegs},
    {"joint-l-knee", "joint-l-ankle", BodyRegion::kLegs},
    {"joint-l-ankle", "joint-l-foot-1", BodyRegion::kFeet},
    {"joint-l-foot-1", "joint-l-foot-2", BodyRegion::kFeet},
    {"joint-r-upper-leg", "joint-r-knee", BodyRegion::kLegs},
    {"joint-r-knee", "joint-r-ankle", BodyRegion::kLegs},
    {"joint-r-ankle", "joint-r-foot-1", BodyRegion::kFeet},
    {"joint-r-foot-1", "joint-r-foot-2", BodyRegion::kFeet},
};

double SegmentDistanceSquared(const Bone& bone, const Eigen::Vector3d& p) {
  const Eigen::Vector3d axis = bone.end - bone.start;
  const double t = std::clamp((p - bone.start).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
  return (bone.start + t * axis - p).squaredNorm();
}

}  // namespace

absl::string_view BodyRegionName(BodyRegion region) {
  static constexpr std::array<absl::string_view, kBodyRegionCount> kNames = {"torso", "arms",
                                                                             "legs", "feet"};
  return kNames[static_cast<int>(region)];
}

absl::StatusOr<std::vector<Bone>> BodyBones(const BodyModel& model,
                                            const core::Positions& full_mesh) {
  if (full_mesh.rows() != kFullVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("skeleton needs the full ", kFullVertexCount,
                                                   "-vertex mesh, got ", full_mesh.rows()));
  }
  auto joint = [&](const char* name) -> absl::StatusOr<Eigen::Vector3d> {
    const std::vector<int32_t> vertices = model.GroupVertices(name);
    if (vertices.empty()) return absl::NotFoundError(absl::StrCat("base.obj has no group ", name));
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int32_t v : vertices) sum += full_mesh.row(v).transpose();
    return sum / static_cast<double>(vertices.size());
  };
  std::vector<Bone> bones;
  for (const BoneSpec& spec : kBones) {
    ASSIGN_OR_RETURN(Eigen::Vector3d start, joint(spec.from));
    ASSIGN_OR_RETURN(Eigen::Vector3d end, joint(spec.to));
    bones.push_back({absl::StrCat(spec.from, "..", spec.to), spec.region, start, end});
  }
  return bones;
}

const Bone& NearestBone(const std::vector<Bone>& bones, const Eigen::Vector3d& point) {
  size_t best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t b = 0; b < bones.size(); ++b) {
    const double d = SegmentDistanceSquared(bones[b], point);
    if (d < best_distance) {
      best_distance = d;
      best = b;
    }
  }
  return bones[best];
}

}  // namespace fitbase::body
