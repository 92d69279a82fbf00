#ifndef FITBASE_BODY_BODY_SKELETON_H_
#define FITBASE_BODY_BODY_SKELETON_H_

#include <string>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "body/body_model.h"
#include "core/mesh.h"

namespace fitbase::body {

// Coarse body regions, for grading and per-region fit reports.
enum class BodyRegion { kTorso = 0, kArms = 1, kLegs = 2, kFeet = 3 };
inline constexpr int kBodyRegionCount = 4;
absl::string_view BodyRegionName(BodyRegion region);

// A bone of hm08's skeleton: the segment between two joint centroids, meters.
struct Bone {
  std::string name;  // "<from>..<to>", e.g. "joint-l-elbow..joint-l-hand".
  BodyRegion region;
  Eigen::Vector3d start;
  Eigen::Vector3d end;
};

// The spine, arm, leg and foot bones of a full hm08 mesh (19,158 x 3, meters), each joint at
// the centroid of its `joint-*` group. Errors: a missing joint group, a wrong vertex count.
absl::StatusOr<std::vector<Bone>> BodyBones(const BodyModel& model,
                                            const core::Positions& full_mesh);

// The bone nearest to `point` (segment distance; ties to the first in order).
const Bone& NearestBone(const std::vector<Bone>& bones, const Eigen::Vector3d& point);

}  // namespace fitbase::body

#endif  // FITBASE_BODY_BODY_SKELETON_H_
